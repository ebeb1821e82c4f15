#include "shadow_setup_pass.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "forest/core/error.hpp"
#include "forest/core/frustum.hpp"
#include "forest/shadows/casters.hpp"
#include "forest/shadows/focus_body.hpp"

namespace forest::render {
namespace {

using glm::dvec2;
using glm::dvec3;

// What the shadow term's filter reads (shaders/shadow_lookup.frag): a hardware 2×2 PCF lookup at a
// point reads the texels whose centres lie less than one texel from it along each map axis, and
// (2r+1)² lookups one texel apart reach r + 1 texels along each axis.
double filterReachTexels(int pcfRadius) { return pcfRadius + 1.0; }
// Beyond the reach: the GPU's float32 lookup coordinates and the rasteriser's fixed-point
// texel-centre test (8 sub-texel bits) — half a texel covers both many times over.
constexpr double kFilterMarginTexels = 0.5;
// The two together: how far from its point a lookup's texels may lie, per map axis.
double filterReachWithMarginTexels(int pcfRadius) { return filterReachTexels(pcfRadius) + kFilterMarginTexels; }

// How far from its point, in texels along each map axis, a pixel's lookup may read: the filter's
// reach, the margin, and the error injection's shift (FrameSettings::lookupShiftTexels).
double lookupReachTexels(const FrameSettings& settings) {
  const double shift = std::max(std::abs(settings.lookupShiftTexels.x), std::abs(settings.lookupShiftTexels.y));
  return filterReachWithMarginTexels(settings.pcfRadius) + std::ceil(shift);
}

// The map keeps this many texels free around B, so that a lookup at B's border reads texels the
// shadow pass drew (DESIGN §4): the reach and the margin, rounded up.
int mapBorderTexels(int pcfRadius) {
  return static_cast<int>(std::ceil(filterReachWithMarginTexels(pcfRadius)));
}

// The largest world distance, across the light, that a map offset of (±1, ±1) texels (the corner
// of the filter's square footprint) spans at p: the inverse of the Jacobian of world (u, v) →
// map texels, exact for the projective map.
double texelCornerWorldSize(const glm::dmat4& worldToShadowClip, int mapSize, const dvec3& p, const dvec3& u, const dvec3& v) {
  const glm::dvec4 h = worldToShadowClip * glm::dvec4(p, 1.0);
  auto column = [&](const dvec3& d) {
    const glm::dvec4 e = worldToShadowClip * glm::dvec4(d, 0.0);
    return (0.5 * mapSize) * (dvec2(e) * h.w - dvec2(h) * e.w) / (h.w * h.w);  // texels per metre
  };
  const glm::dmat2 jacobian(column(u), column(v));
  const double determinant = glm::determinant(jacobian);
  if (!(std::abs(determinant) > 0.0) || !std::isfinite(determinant)) return std::numeric_limits<double>::infinity();
  const glm::dmat2 inverse = glm::inverse(jacobian);
  return std::max(glm::length(inverse * dvec2(1.0, 1.0)), glm::length(inverse * dvec2(1.0, -1.0)));
}

// A receiver box grown so that its projection on the map covers every texel the filter reads for
// a point in it: by reach + margin texels, at the largest texel size over its corners (twice,
// since the grown box reaches where texels may be larger). A box grown by g along every world
// axis contains every point within g of it, so its footprint across the light grows by ≥ g.
Aabb grownByFilter(Aabb box, const shadows::ShadowSetup& setup, int mapSize, double reachTexels, const dvec3& l,
                   const Aabb& sceneBounds) {
  const auto [u, v] = shadows::axesAcrossLight(l);
  const Aabb original = box;
  double grow = 0.0;
  for (int pass = 0; pass < 2; ++pass) {
    double worldPerTexel = 0.0;
    for (int c = 0; c < 8; ++c)
      worldPerTexel = std::max(worldPerTexel, texelCornerWorldSize(setup.worldToShadowClip, mapSize, box.corner(c), u, v));
    grow = std::max(grow, std::min(reachTexels * worldPerTexel, sceneBounds.diagonal()));  // ∞: every caster
    box = Aabb{original.min - dvec3(grow), original.max + dvec3(grow)};
  }
  return box;
}

}  // namespace

int ShadowPlan::sliceOf(double eyeDepth) const {
  int slice = 0;
  while (slice + 1 < cascades && eyeDepth >= slices[static_cast<size_t>(slice)].to) ++slice;
  return slice;
}

int ShadowPlan::layerSide() const {
  int side = 0;
  for (int i = 0; i < cascades; ++i) side = std::max(side, slices[static_cast<size_t>(i)].mapSize);
  return side;
}

// Casters of the visible receivers (DESIGN §4, Bittner et al. 2011): only the part of a receiver
// inside the slice's view receives shadows from its layer, so each box is clipped to that view
// first (a 125 m terrain tile at the edge of the view does not pull in the casters of its unseen
// part), then grown by the filter's footprint in the slice's map. With a receiver mask, a caster
// also has to cover one of its pixels (refineCasters).
void ShadowSetupPass::selectCastersOfReceivers(ShadowSlice& slice, const SliceContext& context, const shadows::ReceiverMask* mask) {
  const FrameSettings& settings = context.settings;
  const dvec3& l = context.l;
  const Aabb& sceneBounds = context.sceneBounds;
  const ConvexBody view = shadows::viewFrustumBody(slice.camera);
  const Frustum viewPlanes(slice.camera);
  const double reach = filterReachWithMarginTexels(settings.pcfRadius);
  footprints_.clear();
  for (const Aabb& receiver : sliceReceivers_) {
    // Most receivers (trees) lie wholly inside V: clipping would return the box itself.
    if (viewPlanes.contains(receiver)) {
      footprints_.push_back(grownByFilter(receiver, slice.setup, slice.mapSize, reach, l, sceneBounds));
      continue;
    }
    ConvexBody part = ConvexBody::fromBox(receiver);
    part.clip(view);
    if (!part.empty()) footprints_.push_back(grownByFilter(part.bounds(), slice.setup, slice.mapSize, reach, l, sceneBounds));
  }
  selector_.rebuild(l, footprints_);
  selectByHierarchy(context.bvh, context.objects.boxes(), slice.casters);
  refineCasters(slice, settings, l, context.objects, context.lod, mask);
}

// A node whose box, swept along the light, meets no receiver holds no object that does (a box
// inside a box sweeps inside its sweep): its subtree is skipped. The same casters as testing every
// object (CasterSelector::select), without a test per tree of a landscape. The top levels' needed
// nodes are dealt to the frame's threads in turn, each walking its nodes' subtrees; the parts'
// casters, merged and sorted, are the same whatever the dealing.
void ShadowSetupPass::selectByHierarchy(const culling::Bvh& bvh, std::span<const Aabb> boxes, std::vector<std::uint32_t>& selected) {
  selected.clear();
  if (bvh.nodes().empty() || selector_.receiverCount() == 0 || !selector_.needed(bvh.nodes()[0].bounds)) return;
  // Breadth-first from the root until there are a few nodes per thread (or only leaves).
  const size_t parts = static_cast<size_t>(workers_.count()), wanted = 8 * parts;
  // A split level at most doubles a frontier of fewer than `wanted`; the two lists trade places
  // each level, so both get that room (a frame then never grows them, DESIGN §9).
  frontier_.reserve(2 * wanted);
  nextFrontier_.reserve(2 * wanted);
  frontier_.assign(1, 0);
  for (bool split = true; split && frontier_.size() < wanted;) {
    split = false;
    nextFrontier_.clear();
    for (std::int32_t n : frontier_) {
      const culling::BvhNode& node = bvh.nodes()[static_cast<size_t>(n)];
      if (node.leaf()) {
        nextFrontier_.push_back(n);
        continue;
      }
      split = true;
      for (std::int32_t child : {node.left, node.right})
        if (selector_.needed(bvh.nodes()[static_cast<size_t>(child)].bounds)) nextFrontier_.push_back(child);
    }
    frontier_.swap(nextFrontier_);
  }
  partStacks_.resize(parts);
  partCasters_.resize(parts);
  // Two pointers in the capture: std::function keeps them without a heap allocation (DESIGN §9).
  const struct {
    const culling::Bvh& bvh;
    std::span<const Aabb> boxes;
  } walk{bvh, boxes};
  workers_.run([this, &walk](int part) {
    std::vector<std::int32_t>& stack = partStacks_[static_cast<size_t>(part)];
    std::vector<std::uint32_t>& out = partCasters_[static_cast<size_t>(part)];
    out.clear();
    for (size_t i = static_cast<size_t>(part); i < frontier_.size(); i += partStacks_.size())
      walkNeededSubtree(walk.bvh, walk.boxes, frontier_[i], stack, out);
  });
  for (const std::vector<std::uint32_t>& part : partCasters_) selected.insert(selected.end(), part.begin(), part.end());
  std::sort(selected.begin(), selected.end());
}

// The objects under `start` whose boxes selector_ needs (`start` is tested again: a few nodes a slice).
void ShadowSetupPass::walkNeededSubtree(const culling::Bvh& bvh, std::span<const Aabb> boxes, std::int32_t start,
                                        std::vector<std::int32_t>& stack, std::vector<std::uint32_t>& out) const {
  stack.assign(1, start);
  while (!stack.empty()) {
    const culling::BvhNode& node = bvh.nodes()[static_cast<size_t>(stack.back())];
    stack.pop_back();
    if (!selector_.needed(node.bounds)) continue;
    if (!node.leaf()) {
      stack.push_back(node.right);
      stack.push_back(node.left);
      continue;
    }
    for (std::uint32_t k = node.first; k < node.first + node.count; ++k) {
      const std::uint32_t o = bvh.objects()[k];
      if (node.count == 1 || selector_.needed(boxes[o])) out.push_back(o);  // a one-object leaf's box is the object's
    }
  }
}

// A caster tile is drawn by its blocks at the level the eye's LOD gives it (Terrain::blockBoxes):
// only those that may write into a backside map for this sun (Terrain::blockMayFaceAway: a block
// whose every triangle faces the sun is culled whole by the pass) and whose own box, swept along
// the light, meets a receiver. A tile none of whose blocks remain is no caster.
// With a receiver mask (Bittner et al. 2011 §4, box casters), a caster or block stays only when its
// box, in the slice's map and grown by the filter's reach, covers a receiver pixel farther from the
// light — for a tree, one of its height slabs (SceneObjects::shapeBoxes), which hug its crown.
void ShadowSetupPass::refineCasters(ShadowSlice& slice, const FrameSettings& settings, const dvec3& l, const SceneObjects& objects,
                                    const terrain::TerrainLod* lod, const shadows::ReceiverMask* mask) {
  const terrain::Terrain* terrain = lod ? objects.terrain() : nullptr;
  if (!terrain && !mask) return;
  slice.terrainByBlock = terrain != nullptr;
  const double reach = filterReachWithMarginTexels(settings.pcfRadius);
  auto covers = [&](const Aabb& box) { return !mask || mask->mayShadow(box, reach); };
  // The trees' tests against the mask, dealt to the frame's threads in turn.
  const size_t count = slice.casters.size();
  treeKept_.assign(count, 1);
  if (mask) {
    const struct {
      const std::vector<std::uint32_t>& casters;
      const SceneObjects& objects;
      const shadows::ReceiverMask& mask;
      double reach;
      size_t parts;
    } test{slice.casters, objects, *mask, reach, static_cast<size_t>(workers_.count())};
    workers_.run([this, &test](int part) {  // (two pointers: no heap allocation)
      for (size_t i = static_cast<size_t>(part); i < test.casters.size(); i += test.parts) {
        const std::uint32_t o = test.casters[i];
        if (test.objects.objects()[o].kind == SceneObjects::Kind::Tile) continue;
        const std::span<const Aabb> shapes = test.objects.shapeBoxes(o);
        treeKept_[i] = std::any_of(shapes.begin(), shapes.end(), [&](const Aabb& box) { return test.mask.mayShadow(box, test.reach); });
      }
    });
  }
  size_t kept = 0;
  for (size_t i = 0; i < count; ++i) {
    const std::uint32_t o = slice.casters[i];
    const SceneObjects::Object& object = objects.objects()[o];
    if (object.kind != SceneObjects::Kind::Tile) {
      if (treeKept_[i]) slice.casters[kept++] = o;
      continue;
    }
    if (!terrain) {
      if (covers(objects.boxes()[o])) slice.casters[kept++] = o;
      continue;
    }
    const int tile = static_cast<int>(object.index), level = terrain->tileLevel(tile, *lod);
    const std::span<const Aabb> blocks = terrain->blockBoxes(tile, level);
    bool any = false;
    for (int b = 0; b < static_cast<int>(blocks.size()); ++b) {
      const Aabb& box = blocks[static_cast<size_t>(b)];
      if (!selector_.needed(box) || !covers(box)) continue;
      // Last, per triangle in a ramp: such a block draws only its runs of cells that may face away.
      cellRuns_.clear();
      if (settings.backside)
        terrain->cellsThatMayFaceAway(tile, level, b, *lod, -l, cellRuns_);
      else
        cellRuns_.push_back({});  // every cell
      for (const terrain::CellSpan& run : cellRuns_) slice.terrainBlocks.push_back({tile, level, b, run});
      any = any || !cellRuns_.empty();
    }
    if (any) slice.casters[kept++] = o;
  }
  slice.casters.resize(kept);
}

// The receiver mask of the slice: the pixels whose eye depth its focus body spans, in its map.
void ShadowSetupPass::fillReceiverMask(const ShadowSlice& slice, const ReceiverPixels& receiverPixels, shadows::ReceiverMask& target) {
  // Cells of 4 texels: finer cells keep fewer casters (LiSPSM 2048², ground view, 75° sun: 4.16×
  // the triangles the truth needs with 8-texel cells, 4.03× with 4, 3.96× with 2), coarser ones
  // are cheaper to clear and scan.
  const int cells = std::clamp(slice.mapSize / 4, 64, 1024);
  // A mask per band of rows (rows dealt in turn: the ground and the sky shared alike), each filled
  // on a thread of its own, then merged.
  const int height = receiverPixels.height();
  const int bands = workers_.count();
  bandMasks_.resize(static_cast<size_t>(bands));
  bandRows_.resize(static_cast<size_t>(bands));
  workers_.run([&](int band) {
    shadows::ReceiverMask& mask = band == 0 ? target : bandMasks_[static_cast<size_t>(band)];
    mask.reset(slice.setup, slice.mapSize, cells);
    std::vector<float>& depths = bandRows_[static_cast<size_t>(band)];
    depths.resize(static_cast<size_t>(receiverPixels.width()));
    for (int y = band; y < height; y += bands) {
      receiverPixels.rowDepths(y, depths);
      mask.addEyeRow(receiverPixels.rays(), receiverPixels.row(y), receiverPixels.columns(), depths, slice.camera.near,
                     slice.camera.far);
    }
  });
  workers_.run([&](int part) {  // each thread merges a share of the cells
    for (size_t band = 1; band < bandMasks_.size(); ++band) target.merge(bandMasks_[band], part, bands);
  });
}

// Zhang et al. 2006 eq. (4) on [z_near, z_f], z_near the nearest visible depth (SDSM, Lauritzen et
// al. 2011: the splits then follow where the view's content lies — the near plane is at 0.2 m, the
// ground in a standing view ~3 m away or more). The first slice still serves everything from the
// camera's near plane on, since z_near is a frame old. The inner splits move over time like n
// (kNearDistanceSmoothing of the way in log depth per frame, both ways), so a jump of z_f or z_near
// does not move every slice's texels at once; a smoothed split that would leave the range or pass
// the split below takes the new value.
shadows::SplitDepths ShadowSetupPass::splitsFor(const Camera& camera, double farDepth, std::optional<double> nearestDepth,
                                                const ShadowSettings& cascades) {
  double zNear = std::clamp(nearestDepth.value_or(camera.near), camera.near, farDepth);
  if (!(zNear * (1.0 + 1e-6) < farDepth)) zNear = camera.near;
  shadows::SplitDepths target = shadows::cascadeSplits(zNear, farDepth, cascades.cascades, cascades.split_lambda);
  target[0] = camera.near;
  const shadows::SplitDepths splits = shadows::smoothSplits(target, previousSplits_);
  previousSplits_ = splits;
  return splits;
}

void ShadowSetupPass::run(const Camera& camera, const culling::CullingResult& visible, const FrameSettings& settings,
                          const ShadowSettings& cascades, std::optional<double> nearestDepth, const dvec3& l,
                          bool sunBelowHorizon, const SceneObjects& objects, const culling::Bvh& bvh, const terrain::TerrainLod* lod,
                          const Aabb& sceneBounds, const ReceiverPixels* receiverPixels, std::span<const std::uint8_t> shownObjects,
                          ShadowPlan& plan, FrameStats& stats) {
  startPlan(camera, visible, shownObjects, objects, lod, cascades, plan, stats);
  for (int i = 0; i < plan.cascades; ++i) {
    plan.slices[static_cast<size_t>(i)].mapSize = sliceMapSize(settings, i, plan.cascades);
    stats.cascade[static_cast<size_t>(i)].mapSize = plan.slices[static_cast<size_t>(i)].mapSize;
  }
  if (!settings.keepSlices) kept_.reset();
  plan.lookupReachTexels = lookupReachTexels(settings);
  plan.shadowed = !sunBelowHorizon && !receivers_.empty() && sceneBounds.valid();
  if (!plan.shadowed) return;

  const bool onReceivers = settings.focus == FocusBound::Receivers;
  const double farDepth = onReceivers ? std::max(visible.farDepth, camera.near * 1.001) : camera.far;
  const shadows::SplitDepths splits = splitsFor(camera, farDepth, nearestDepth, cascades);
  stats.nearestDepth = nearestDepth.value_or(camera.near);
  measureReceiverDepths(camera);
  const SliceContext context{settings, l, objects, bvh, lod, sceneBounds, receiverPixels};
  for (int i = 0; i < plan.cascades; ++i) {
    ShadowSlice& slice = plan.slices[static_cast<size_t>(i)];
    const size_t s = static_cast<size_t>(i);
    slice.from = splits[s];
    slice.to = splits[s + 1];
    // B reaches past the split into the next slice's blend band (its pixels mix both layers).
    slice.camera = shadows::sliceCamera(camera, splits, i, plan.blend);
    shadows::ShadowInput input = sliceInput(slice, i, plan.cascades > 1 && i == 0 ? nearestDepth : std::nullopt, context);
    if (const std::optional<std::string> outside = shadows::outsideShadowDomain(input)) {
      // A view too shallow for float32 this far from the origin: no shadows this frame, and why.
      plan.shadowed = false;
      outsideNote_ = *outside;  // kept here: the diagnostics hold a view of it
      stats.shadow.fallback = outsideNote_;
      return;
    }
    CascadeStats& out = stats.cascade[s];
    out.keeping = shadows::SliceKeeping{};
    if (onReceivers && !input.receivers->valid()) {
      slice.setup = shadows::ShadowSetup{};  // nothing visible at these depths: the layer stays clear
      slice.setup.diagnostics.fallback = "no receivers in the slice";
    } else if (settings.keepSlices) {
      slice.setup = kept_.setup(input, settings.method, i, settings.keepLimits, out.keeping);
    } else {
      slice.setup = shadows::computeShadowSetup(input, settings.method);
    }
    history_.remember(settings.method, i, slice.setup);
    if (!slice.setup.empty) selectCasters(slice, i, context);
    out.fromM = slice.from;
    out.toM = slice.to;
    out.n = slice.setup.diagnostics.n;
    out.gammaDeg = slice.setup.diagnostics.gammaDeg;
    out.casters = static_cast<int>(slice.casters.size());
  }
  stats.shadow = plan.slices[0].setup.diagnostics;
}

// The receivers and the slices' lists emptied, with room for every object (and block) as receiver
// and caster (a frame then never grows them). A receiver is a visible object's box; a visible
// terrain tile's are its blocks at the level the eye's LOD draws it that meet the view frustum (their
// union holds everything drawn of the tile in view, Terrain::blockBoxes): a 125 m tile's box rises
// far above the ground in view, and B bounded by it reached above the eye (issue "Shadows that hold
// still", item 1: the near band's loss at a high sun). With the read-back's record, a box selects
// casters only where its object has pixels: the culler's set holds whole BVH leaves ([culling]
// leaf_size) and what its queries could not rule out, a superset of what the image shows; a pixel
// lies in its own object's box, so the mask's pixels all keep their casters.
void ShadowSetupPass::startPlan(const Camera& camera, const culling::CullingResult& visible, std::span<const std::uint8_t> shownObjects,
                                const SceneObjects& objects, const terrain::TerrainLod* lod, const ShadowSettings& cascades,
                                ShadowPlan& plan, FrameStats& stats) {
  const size_t objectCount = objects.boxes().size();
  const size_t mostBlocks = objects.tileCount() * terrain::Terrain::kMaxBlockBoxes;
  receivers_.reserve(objectCount + mostBlocks);
  receiverSelects_.reserve(objectCount + mostBlocks);
  sliceReceivers_.reserve(objectCount + mostBlocks);
  receiverDepths_.reserve(objectCount + mostBlocks);
  footprints_.reserve(objectCount + mostBlocks);
  selector_.reserve(objectCount + mostBlocks);
  receivers_.clear();
  receiverSelects_.clear();
  stats.casterReceivers = 0;
  const terrain::Terrain* terrain = lod ? objects.terrain() : nullptr;
  const Frustum view(camera);
  for (std::uint32_t o : visible.visibleObjects) {
    const SceneObjects::Object& object = objects.objects()[o];
    const std::uint8_t selects = shownObjects.empty() || shownObjects[o] != 0 ? 1 : 0;
    stats.casterReceivers += selects;
    if (!terrain || object.kind != SceneObjects::Kind::Tile) {
      receivers_.push_back(objects.boxes()[o]);
      receiverSelects_.push_back(selects);
      continue;
    }
    const int tile = static_cast<int>(object.index);
    for (const Aabb& block : terrain->blockBoxes(tile, terrain->tileLevel(tile, *lod)))
      if (view.mayIntersect(block)) {
        receivers_.push_back(block);
        receiverSelects_.push_back(selects);
      }
  }
  plan.cascades = cascades.cascades;
  plan.blend = cascades.cascade_blend;
  stats.cascades = cascades.cascades;
  stats.splitLambda = cascades.split_lambda;
  stats.cascadeBlend = cascades.cascade_blend;
  for (ShadowSlice& slice : plan.slices) {
    slice.casters.reserve(objectCount);
    slice.casters.clear();
    slice.terrainBlocks.reserve(mostBlocks);
    slice.terrainBlocks.clear();
    slice.terrainByBlock = false;
    slice.texelsRead.reset();
    slice.receiverMask = nullptr;
  }
}

// Each receiver's eye-depth range, for the slices it reaches.
void ShadowSetupPass::measureReceiverDepths(const Camera& camera) {
  const dvec3 forward = camera.forward();
  receiverDepths_.clear();
  for (const Aabb& box : receivers_) {
    dvec2 range(std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity());
    for (int c = 0; c < 8; ++c) {
      const double depth = glm::dot(box.corner(c) - camera.position, forward);
      range = dvec2(std::min(range.x, depth), std::max(range.y, depth));
    }
    receiverDepths_.push_back(range);
  }
}

// The slice's receivers (sliceReceivers_: those that select casters) and its setup's input: B
// bounded by all of them, what the method carried from the last frame, n from the nearest depth for
// the first of several slices.
shadows::ShadowInput ShadowSetupPass::sliceInput(const ShadowSlice& slice, int index, std::optional<double> nNear,
                                                 const SliceContext& context) {
  sliceReceivers_.clear();
  Aabb sliceBounds;
  for (size_t r = 0; r < receivers_.size(); ++r)
    if (receiverDepths_[r].y >= slice.camera.near && receiverDepths_[r].x <= slice.camera.far) {
      if (receiverSelects_[r] != 0) sliceReceivers_.push_back(receivers_[r]);
      sliceBounds.extend(receivers_[r]);
    }
  const FrameSettings& settings = context.settings;
  shadows::ShadowInput input;
  input.camera = slice.camera;
  input.sunDirection = context.l;
  input.scene = context.sceneBounds;
  if (settings.focus == FocusBound::Receivers) input.receivers = sliceBounds;
  // What the method carried from the last frame (lispsm: n over time, §9.2.5; uniform-stable: its radius).
  input.carried = history_.carried(settings.method, index);
  // The first slice serves everything from the near plane, but nothing visible lies nearer than
  // z_near: its n is eq. 8.13 from there (ShadowInput::nNear); B still starts at the near plane.
  input.nNear = nNear;
  input.mapSize = slice.mapSize;
  input.borderTexels = mapBorderTexels(settings.pcfRadius);
  return input;
}

// The casters the slice's layer draws, by the frame's caster selection.
void ShadowSetupPass::selectCasters(ShadowSlice& slice, int index, const SliceContext& context) {
  const FrameSettings& settings = context.settings;
  const std::size_t objectCount = context.objects.boxes().size();
  switch (settings.casters) {
    case CasterSelection::Receivers:
    case CasterSelection::ReceiverMaskGpu:  // the trees among them tested on the GPU (ShadowPass)
      selectCastersOfReceivers(slice, context, nullptr);
      break;
    case CasterSelection::ReceiverPixels:
      if (!context.receiverPixels) throw Error("shadow setup: receiver-pixels casters without the receiver pixels");
    {
      shadows::ReceiverMask& mask = masks_[static_cast<size_t>(index)];
      fillReceiverMask(slice, *context.receiverPixels, mask);
      slice.texelsRead = mask.texelsRead(lookupReachTexels(settings));
      slice.receiverMask = &mask;
      selectCastersOfReceivers(slice, context, &mask);
      break;
    }
    case CasterSelection::FrustumBody: {
      const ConvexBody body = shadows::computeFocusBody(slice.camera, context.l, context.sceneBounds);
      for (std::uint32_t o = 0; o < objectCount; ++o)
        if (shadows::mayIntersect(body, context.objects.boxes()[o])) slice.casters.push_back(o);
      break;
    }
    case CasterSelection::All:
      for (std::uint32_t o = 0; o < objectCount; ++o) slice.casters.push_back(o);
      break;
  }
}

}  // namespace forest::render
