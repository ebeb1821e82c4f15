#include "caster_occlusion.hpp"

#include <algorithm>
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

CasterOcclusion::CasterOcclusion(const SceneObjects& objects)
    : objects_(objects), counted_(objects.treeCount(), 0), marked_(objects.treeCount(), 0) {}

void CasterOcclusion::beginFrame() {
  counted_.swap(marked_);
  std::fill(marked_.begin(), marked_.end(), std::uint8_t{0});
}

long long CasterOcclusion::triangles(std::uint32_t tree, const dvec3& eye) const {
  const vegetation::Forest& forest = *objects_.forest();
  const vegetation::Species species = forest.trees()[tree].species;
  return forest.model(species).lods[static_cast<size_t>(forest.lodFor(tree, eye))].triangleCount();
}

bool CasterOcclusion::worthCulling(std::span<const std::uint32_t> casters, long long texels, const dvec3& eye) {
  double expected = 0.0;
  for (std::uint32_t o : casters) {
    const SceneObjects::Object& object = objects_.objects()[o];
    if (object.kind != SceneObjects::Kind::Tree || counted_[object.index] != 0) continue;
    expected += culledShare_ * static_cast<double>(triangles(object.index, eye));
    if (expected * kTexelsPerTriangle >= static_cast<double>(texels)) return true;
  }
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
                                   const dvec3& eye, std::vector<std::uint32_t>& trees) {
  if (mask.everywhere() || rect.empty()) return;  // a receiver the map cannot place: keep them all
  clipToWorld_ = glm::inverse(setup.worldToShadowClip);
  long long tested = 0, culled = 0;
  const auto hidden = [&](std::uint32_t o) {
    const std::uint32_t tree = objects_.objects()[o].index;
    const long long t = triangles(tree, eye);
    tested += t;
    if (treeMayShow(tree, setup, mapSize, mask, reachTexels, rect, depths)) return false;
    culled += t;
    return true;
  };
  trees.erase(std::remove_if(trees.begin(), trees.end(), hidden), trees.end());
  culledShare_ = tested > 0 ? std::max(0.01, static_cast<double>(culled) / static_cast<double>(tested)) : culledShare_;
}

// Whether one of the tree's crown slabs may lower a texel of the layer that a receiver beyond it
// reads (keepUnhidden).
bool CasterOcclusion::treeMayShow(std::uint32_t tree, const shadows::ShadowSetup& setup, int mapSize, const shadows::ReceiverMask& mask,
                                  double reachTexels, const shadows::TexelRect& rect, std::span<const float> depths) {
  slabs_.clear();
  objects_.forest()->placedCasterSlabs(tree, slabs_);
  const auto depthOf = [&](const dvec3& p) {
    const dvec4 h = setup.worldToShadowClip * dvec4(p, 1.0);
    return h.z / h.w;
  };
  for (const vegetation::PlacedCrownSlab& slab : slabs_) {
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
