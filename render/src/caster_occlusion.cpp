#include "caster_occlusion.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

namespace forest::render {

using glm::dvec2;
using glm::dvec3;
using glm::dvec4;

namespace {
// A fragment is made only at a texel centre; this much of a texel covers float32 and the
// rasteriser's sub-texel snapping (as caster_filter.comp's kCentreMargin).
constexpr double kCentreMargin = 1.0 / 16.0;
// Map depth (clip z / w) that float32 placement on the GPU may miss by, both ways.
constexpr double kDepthTolerance = 2e-5;
// A slab whose footprint spans more texels than this is kept untested: a tree that near the eye
// is nearly always one that counted, and the test would cost more than its draw.
constexpr long long kLargestTestedTexels = 64 * 64;
// A texel read back (its depth and its object ID) costs about what 1/64 of a shadow triangle
// does: llvmpipe on 2 cores, the landscape walk at 5000 trees (bench scale): the read-backs and
// tests added ~21 ms p50 over the read rectangles, where 52 k triangles took ~24 ms (≈ 80 texels
// a triangle; rounded down, so that a layer is culled a little sooner).
constexpr long long kTexelsPerTriangle = 64;
}  // namespace

CasterOcclusion::CasterOcclusion(const SceneObjects& objects, WorkerThreads& workers)
    : objects_(objects), counted_(objects.treeCount(), 0), marked_(objects.treeCount(), 0), workers_(workers),
      slabs_(static_cast<size_t>(workers.count())),
      tested_(static_cast<size_t>(workers.count())),
      culled_(static_cast<size_t>(workers.count())) {}

void CasterOcclusion::beginFrame() {
  counted_.swap(marked_);
  std::fill(marked_.begin(), marked_.end(), std::uint8_t{0});
}

long long CasterOcclusion::triangles(std::uint32_t tree, const dvec3& eye, const ImpostorSwitch& impostors) const {
  const vegetation::Forest& forest = *objects_.forest();
  const double share = impostorShare(impostors, forest.lodDistance(tree, eye));
  const vegetation::Species species = forest.trees()[tree].species;
  const long long mesh = share < 1.0 ? forest.model(species).lods[static_cast<size_t>(forest.lodFor(tree, eye))].triangleCount() : 0;
  return mesh + (share > 0.0 ? kImpostorTriangles : 0);
}

bool CasterOcclusion::worthCulling(std::span<const std::uint32_t> casters, long long texels, const dvec3& eye,
                                   const ImpostorSwitch& impostors) {
  double expected = 0.0, tested = 0.0;
  for (std::uint32_t o : casters) {
    const SceneObjects::Object& object = objects_.objects()[o];
    if (object.kind != SceneObjects::Kind::Tree || counted_[object.index] != 0) continue;
    expected += culledShare_ * static_cast<double>(triangles(object.index, eye, impostors));
    tested += 1.0;
  }
  // In triangles' time: the read-backs at kTexelsPerTriangle texels a triangle, the test at its
  // measured price (0 until measured: the read-backs alone decide, as on a first layer).
  const double testTriangles = msPerTriangle_ > 0.0 ? tested * msPerTestedTree_ / msPerTriangle_ : 0.0;
  if (expected >= static_cast<double>(texels) / kTexelsPerTriangle + testTriangles) return true;
  culledShare_ = std::min(1.0, culledShare_ * 1.1);
  return false;
}

void CasterOcclusion::split(std::span<const std::uint32_t> casters, std::vector<std::uint32_t>& first,
                            std::vector<std::uint32_t>& others) const {
  first.clear();
  others.clear();
  for (std::uint32_t o : casters) {
    const SceneObjects::Object& object = objects_.objects()[o];
    const bool later = object.kind == SceneObjects::Kind::Tree && counted_[object.index] == 0;
    (later ? others : first).push_back(o);
  }
}

void CasterOcclusion::keepUnhidden(const shadows::ShadowSetup& setup, int mapSize, const shadows::ReceiverMask& mask,
                                   double reachTexels, const shadows::TexelRect& rect, std::span<const float> depths,
                                   const dvec3& eye, const ImpostorSwitch& impostors,
                                   std::vector<std::uint32_t>& trees) {
  if (mask.everywhere() || rect.empty()) return;  // a receiver the map cannot place: keep them all
  clipToWorld_ = glm::inverse(setup.worldToShadowClip);
  heldDepths_.build(depths, rect.x1 - rect.x0, rect.y1 - rect.y0);
  const auto testStart = std::chrono::steady_clock::now();
  // The trees in runs of 64 dealt round the parts (neighbouring trees cost alike).
  constexpr size_t kRun = 64;
  const size_t parts = static_cast<size_t>(workers_.count());
  keep_.assign(trees.size(), 0);
  std::fill(tested_.begin(), tested_.end(), 0);
  std::fill(culled_.begin(), culled_.end(), 0);
  workers_.run([&](int part) {
    const size_t p = static_cast<size_t>(part);
    std::vector<vegetation::PlacedCrownSlab>& slabs = slabs_[p];
    for (size_t start = p * kRun; start < trees.size(); start += parts * kRun)
      for (size_t i = start; i < std::min(trees.size(), start + kRun); ++i) {
        const std::uint32_t tree = objects_.objects()[trees[i]].index;
        const long long t = triangles(tree, eye, impostors);
        tested_[p] += t;
        slabs.clear();
        objects_.forest()->placedCasterSlabs(tree, slabs);
        keep_[i] = !hiddenByHeldDepths(slabs, setup, mapSize, rect) && treeMayShow(slabs, setup, mapSize, mask, reachTexels, rect, depths);
        if (!keep_[i]) culled_[p] += t;
      }
  });
  size_t kept = 0;
  for (size_t i = 0; i < trees.size(); ++i)
    if (keep_[i]) trees[kept++] = trees[i];
  trees.resize(kept);
  long long testedAll = 0, culledAll = 0;
  for (size_t p = 0; p < parts; ++p) {
    testedAll += tested_[p];
    culledAll += culled_[p];
  }
  culledShare_ = testedAll > 0 ? std::max(0.01, static_cast<double>(culledAll) / static_cast<double>(testedAll)) : culledShare_;
  lastTestMs_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - testStart).count();
  lastTested_ = keep_.size();
}

void CasterOcclusion::measuredCosts(double drawMs, std::span<const std::uint32_t> drawn, const dvec3& eye,
                                    const ImpostorSwitch& impostors) {
  long long drawnTriangles = 0;
  for (std::uint32_t o : drawn)
    if (objects_.objects()[o].kind == SceneObjects::Kind::Tree) drawnTriangles += triangles(objects_.objects()[o].index, eye, impostors);
  if (drawnTriangles == 0 || lastTested_ == 0) return;  // nothing to price by
  msPerTriangle_ = drawMs / static_cast<double>(drawnTriangles);
  msPerTestedTree_ = lastTestMs_ / static_cast<double>(lastTested_);
}

// Whether the tree's slabs lie at or beyond the largest depth the layer holds over the texels
// they may cover. The box around them, grown by the most treeMayShow grows a slab (a texel's
// kCentreMargin at one texel per slab, plus 0.01 m: PlacedCrownSlab::grownBounds), bounds every
// point its line test can take as an entry; a projective map with w > 0 over the box takes its least depth at a corner
// (z/w is linear-fractional along every line). Where that least depth is not nearer than any depth
// held over the box's texels, no slab's entry is nearer than the layer at any texel it covers, and
// treeMayShow would return false: deciding here changes no tree's fate, only the time.
bool CasterOcclusion::hiddenByHeldDepths(std::span<const vegetation::PlacedCrownSlab> slabs, const shadows::ShadowSetup& setup, int mapSize,
                                         const shadows::TexelRect& rect) const {
  Aabb corners;  // the slabs' corners' box: a slab's extent in treeMayShow is within it
  for (const vegetation::PlacedCrownSlab& slab : slabs) corners.extend(slab.grownBounds(0.0));
  if (!corners.valid()) return true;  // no slab: nothing the exact test would keep
  const double grow = kCentreMargin * corners.diagonal() + 0.01;
  Aabb box;
  for (const vegetation::PlacedCrownSlab& slab : slabs) box.extend(slab.grownBounds(grow));
  dvec2 lo(std::numeric_limits<double>::infinity()), hi(-lo);
  double nearest = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 8; ++i) {
    const dvec3 c = box.corner(i);
    const dvec4 h = setup.worldToShadowClip * dvec4(c, 1.0);
    if (!(h.w > 0.0)) return false;  // behind the light's projection: left to the exact test
    const dvec2 t = (dvec2(h) / h.w * 0.5 + 0.5) * static_cast<double>(mapSize);
    if (!std::isfinite(t.x) || !std::isfinite(t.y) || !std::isfinite(h.z / h.w)) return false;
    lo = glm::min(lo, t);
    hi = glm::max(hi, t);
    nearest = std::min(nearest, h.z / h.w);
  }
  // The texel centres it may cover inside the rectangle drawn (as treeMayShow's per slab).
  const int x0 = std::max(rect.x0, static_cast<int>(std::ceil(lo.x - 0.5 - kCentreMargin)));
  const int x1 = std::min(rect.x1 - 1, static_cast<int>(std::floor(hi.x - 0.5 + kCentreMargin)));
  const int y0 = std::max(rect.y0, static_cast<int>(std::ceil(lo.y - 0.5 - kCentreMargin)));
  const int y1 = std::min(rect.y1 - 1, static_cast<int>(std::floor(hi.y - 0.5 + kCentreMargin)));
  if (x0 > x1 || y0 > y1) return true;  // no texel centre the pass draws
  return notNearerThanHeld(nearest, rect, x0, y0, x1, y1);
}

// Whether map depth `nearest` (clip z / w) is at or beyond every depth the layer holds over texels
// [x0, x1] × [y0, y1] (stored in [0, 1]), less the float32 placement's tolerance.
bool CasterOcclusion::notNearerThanHeld(double nearest, const shadows::TexelRect& rect, int x0, int y0, int x1, int y1) const {
  const double farthestHeld = 2.0 * static_cast<double>(heldDepths_.maxOver(x0 - rect.x0, y0 - rect.y0, x1 - rect.x0, y1 - rect.y0)) - 1.0;
  return nearest - kDepthTolerance >= farthestHeld;
}

// Whether every point of `grown` (the box around a slab grown by its line test's margin) lies at
// or beyond the largest depth held over texels [x0, x1] × [y0, y1]: then no line through them
// enters it nearer than the layer (hiddenByHeldDepths' argument, for one slab).
bool CasterOcclusion::slabBehindHeldDepths(const Aabb& grown, const shadows::ShadowSetup& setup, const shadows::TexelRect& rect, int x0,
                                           int y0, int x1, int y1) const {
  double nearest = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 8; ++i) {
    const dvec4 h = setup.worldToShadowClip * dvec4(grown.corner(i), 1.0);
    if (!(h.w > 0.0) || !std::isfinite(h.z / h.w)) return false;
    nearest = std::min(nearest, h.z / h.w);
  }
  return notNearerThanHeld(nearest, rect, x0, y0, x1, y1);
}

// Whether one of the tree's crown slabs may lower a texel of the layer that a receiver
// beyond it reads (keepUnhidden).
bool CasterOcclusion::treeMayShow(std::span<const vegetation::PlacedCrownSlab> slabs, const shadows::ShadowSetup& setup, int mapSize,
                                  const shadows::ReceiverMask& mask, double reachTexels, const shadows::TexelRect& rect,
                                  std::span<const float> depths) const {
  const auto depthOf = [&](const dvec3& p) {
    const dvec4 h = setup.worldToShadowClip * dvec4(p, 1.0);
    return h.z / h.w;
  };
  for (const vegetation::PlacedCrownSlab& slab : slabs) {
    // The slab's footprint in texels, and its extent (for the margin in the world).
    dvec2 lo(std::numeric_limits<double>::infinity()), hi(-lo);
    Aabb extent;
    for (const dvec3& c : slab.corners()) {
      const dvec4 h = setup.worldToShadowClip * dvec4(c, 1.0);
      if (!(h.w > 0.0)) return true;  // behind the light's projection
      const dvec2 t = (dvec2(h) / h.w * 0.5 + 0.5) * static_cast<double>(mapSize);
      if (!std::isfinite(t.x) || !std::isfinite(t.y)) return true;
      lo = glm::min(lo, t);
      hi = glm::max(hi, t);
      extent.extend(c);
    }
    // The texel centres it may cover, inside the rectangle the pass draws into.
    const int x0 = std::max(rect.x0, static_cast<int>(std::ceil(lo.x - 0.5 - kCentreMargin)));
    const int x1 = std::min(rect.x1 - 1, static_cast<int>(std::floor(hi.x - 0.5 + kCentreMargin)));
    const int y0 = std::max(rect.y0, static_cast<int>(std::ceil(lo.y - 0.5 - kCentreMargin)));
    const int y1 = std::min(rect.y1 - 1, static_cast<int>(std::floor(hi.y - 0.5 + kCentreMargin)));
    if (x0 > x1 || y0 > y1) continue;  // no texel centre the pass draws: this slab writes nothing
    if (static_cast<long long>(x1 - x0 + 1) * (y1 - y0 + 1) > kLargestTestedTexels) return true;
    // kCentreMargin of a texel in the world, at the largest world size per texel the slab spans.
    const dvec2 texels = glm::max(hi - lo, dvec2(1.0));
    const double grow = kCentreMargin * extent.diagonal() / std::min(texels.x, texels.y) + 0.01;
    if (slabBehindHeldDepths(slab.grownBounds(grow), setup, rect, x0, y0, x1, y1)) continue;
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const std::optional<double> farthest = mask.farthestReading(x, y, reachTexels);
        if (!farthest) continue;  // no lookup reads the texel
        // The light's line through the texel centre: the points whose map x, y are the centre's.
        const dvec2 ndc = (dvec2(x, y) + 0.5) / static_cast<double>(mapSize) * 2.0 - 1.0;
        const dvec4 h0 = clipToWorld_ * dvec4(ndc, -1.0, 1.0), h1 = clipToWorld_ * dvec4(ndc, 1.0, 1.0);
        const dvec3 a = dvec3(h0) / h0.w, d = dvec3(h1) / h1.w - a;
        const std::optional<dvec2> span = slab.lineSpan(a, d, grow);
        if (!span) continue;
        const double entry = std::min(depthOf(a + span->x * d), depthOf(a + span->y * d)) - kDepthTolerance;
        if (entry > *farthest) continue;  // behind every receiver that reads the texel
        const double held = 2.0 * depths[static_cast<size_t>(y - rect.y0) * static_cast<size_t>(rect.x1 - rect.x0) + (x - rect.x0)] - 1.0;
        if (entry < held) return true;
      }
  }
  return false;
}

void CasterOcclusion::markCounted(const shadows::ReceiverMask& mask, double reachTexels, const shadows::TexelRect& rect,
                                  std::span<const std::uint32_t> ids) {
  const std::uint32_t treeIdBase = objects_.treeIdBase(), trees = static_cast<std::uint32_t>(objects_.treeCount());
  const size_t width = static_cast<size_t>(rect.x1 - rect.x0);
  mask.forEachTexelRead(reachTexels, [&](int x, int y) {
    if (x < rect.x0 || x >= rect.x1 || y < rect.y0 || y >= rect.y1) return;
    const std::uint32_t tree = ids[static_cast<size_t>(y - rect.y0) * width + (x - rect.x0)] - treeIdBase;
    if (tree < trees) marked_[tree] = 1;
  });
}

}  // namespace forest::render
