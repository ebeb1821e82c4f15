#pragma once
// Pass 2 of the frame (DESIGN §1, §4, thesis §9.2): from the visible set to the light. The visible
// depth range is split into slices (one without cascades; Zhang et al. 2006 eq. 4 between the
// nearest visible depth and z_f); per slice the focus body B of its visible receivers, the shadow
// setup of the chosen method (n smoothed over time, §9.2.5) and the casters its layer draws. CPU only.
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "forest/culling/bvh.hpp"
#include "forest/culling/occlusion_culler.hpp"
#include "forest/render/frame.hpp"
#include "forest/render/scene_objects.hpp"
#include "forest/shadows/cascades.hpp"
#include "forest/shadows/casters.hpp"
#include "forest/shadows/kept_slices.hpp"
#include "forest/shadows/method_history.hpp"
#include "forest/shadows/receiver_mask.hpp"
#include "forest/shadows/shadow_setup.hpp"
#include "receiver_pixels.hpp"
#include "worker_threads.hpp"

namespace forest::render {

// One slice's part of the plan.
struct ShadowSlice {
  double from = 0.0, to = 0.0;          // eye depths it serves: [from, to)
  Camera camera;                        // the eye camera with near, far = the ends of its focus body (shadows::sliceCamera)
  int mapSize = 0;                      // its layer's texels per side (sliceMapSize): the square at the layer's origin
  shadows::ShadowSetup setup;
  std::vector<std::uint32_t> casters;   // object indices (a terrain tile when any of its blocks is drawn)
  // The terrain casters by block (CasterSelection::Receivers): the blocks of the caster tiles that
  // may write into the backside map and whose boxes meet a receiver. Otherwise the tiles whole.
  bool terrainByBlock = false;
  std::vector<terrain::TileBlock> terrainBlocks;
  // With the receiver pixels known (CasterSelection::ReceiverPixels): the texels this frame's
  // lookups can read (shadows::ReceiverMask::texelsRead), the only ones the shadow pass needs to
  // draw into. Unset: the whole layer.
  std::optional<shadows::TexelRect> texelsRead;
  // Its receiver mask (CasterSelection::ReceiverPixels; else null): the shadow pass culls the trees
  // hidden from the sun with it (CasterOcclusion). Held by the setup pass until its next frame.
  const shadows::ReceiverMask* receiverMask = nullptr;
};

// What the shadow pass and the shadow term work from. Kept from the last frame that had a sun and
// receivers.
struct ShadowPlan {
  bool shadowed = false;  // sun up, something visible: the map is drawn
  int cascades = 1;
  double blend = 0.0;     // the blend band's share of a split's distance
  // How far from its point, in texels along each map axis, a pixel's lookup may read (the filter's
  // reach, its margin, an injected shift): what a caster's footprint is grown by.
  double lookupReachTexels = 0.0;
  std::array<ShadowSlice, shadows::kMaxCascades> slices;
  // The slice a pixel at eye depth z reads (the shader's choice, shadow_lookup.frag).
  int sliceOf(double eyeDepth) const;
  // Texels per side of the array texture that holds every slice's layer: the largest mapSize.
  int layerSide() const;
};

class ShadowSetupPass {
 public:
  // `workers`: the frame's CPU threads (the receiver mask's bands).
  explicit ShadowSetupPass(WorkerThreads& workers) : workers_(workers) {}
  // Fills `plan` (and the shadow statistics) for this frame's visible set. `l`: the unit light
  // direction; `sceneBounds`: S; `nearestDepth`: the nearest visible eye depth when known (the
  // first slice's split scheme starts there).
  // `lod`: the eye's terrain LOD (the shadow pass draws it; null without terrain).
  // `receiverPixels`: this frame's visible sun-facing pixels, read for
  // CasterSelection::ReceiverPixels; null otherwise. `shownObjects`: per object, nonzero where it
  // has a pixel in that read-back (ImageVisibility::shownObjects); only those visible objects
  // select casters, while B and z_f stay the visible set's. Empty: every visible object selects.
  void run(const Camera& camera, const culling::CullingResult& visible, const FrameSettings& settings,
           const ShadowSettings& cascades, std::optional<double> nearestDepth, const glm::dvec3& l, bool sunBelowHorizon,
           const SceneObjects& objects, const culling::Bvh& bvh, const terrain::TerrainLod* lod, const Aabb& sceneBounds,
           const ReceiverPixels* receiverPixels, std::span<const std::uint8_t> shownObjects, ShadowPlan& plan, FrameStats& stats);
  // Forgets the smoothed n and splits, the stable maps' radii and the kept maps (a camera cut).
  void reset() {
    history_.reset();
    kept_.reset();
    previousSplits_ = {};
  }

 private:
  // What every slice's setup and caster selection read.
  struct SliceContext {
    const FrameSettings& settings;
    const glm::dvec3& l;
    const SceneObjects& objects;
    const culling::Bvh& bvh;  // over objects.boxes()
    const terrain::TerrainLod* lod;
    const Aabb& sceneBounds;
    const ReceiverPixels* receiverPixels;
  };
  // The steps of run(), in order.
  void startPlan(const Camera& camera, const culling::CullingResult& visible, std::span<const std::uint8_t> shownObjects,
                 const SceneObjects& objects, const terrain::TerrainLod* lod, const ShadowSettings& cascades, ShadowPlan& plan,
                 FrameStats& stats);
  void measureReceiverDepths(const Camera& camera);
  shadows::ShadowInput sliceInput(const ShadowSlice& slice, int index, std::optional<double> nNear, const SliceContext& context);
  void selectCasters(ShadowSlice& slice, int index, const SliceContext& context);
  // The split depths of [camera near, z_f]: Zhang's scheme from z_near, the inner splits smoothed.
  shadows::SplitDepths splitsFor(const Camera& camera, double farDepth, std::optional<double> nearestDepth,
                                 const ShadowSettings& cascades);
  // Casters of the slice's receivers (DESIGN §4): each receiver's part inside the slice's view,
  // grown by the filter's footprint, swept along the light (shadows::CasterSelector); then
  // refineCasters.
  // The objects whose boxes selector_ needs, in increasing order, found down the BVH.
  void selectByHierarchy(const culling::Bvh& bvh, std::span<const Aabb> boxes, std::vector<std::uint32_t>& selected);
  void walkNeededSubtree(const culling::Bvh& bvh, std::span<const Aabb> boxes, std::int32_t start, std::vector<std::int32_t>& stack,
                         std::vector<std::uint32_t>& out) const;
  void selectCastersOfReceivers(ShadowSlice& slice, const SliceContext& context, const shadows::ReceiverMask* mask);
  // Replaces the caster tiles by their blocks that may write into the map and meet a receiver
  // (selector_ must hold the slice's receivers), and with a mask keeps only the casters and blocks
  // that may darken one of its pixels.
  void refineCasters(ShadowSlice& slice, const FrameSettings& settings, const glm::dvec3& l, const SceneObjects& objects,
                     const terrain::TerrainLod* lod, const shadows::ReceiverMask* mask);
  // `mask` over the visible sun-facing pixels whose eye depth the slice's focus body spans.
  void fillReceiverMask(const ShadowSlice& slice, const ReceiverPixels& receiverPixels, shadows::ReceiverMask& mask);

  shadows::MethodHistory history_;  // what the shadow method carries from frame to frame, per slice
  shadows::KeptSlices kept_;        // the slices' kept maps (FrameSettings::keepSlices)
  std::string outsideNote_;  // why a view got no shadows (outside float32's domain): the stats' fallback views it
  shadows::SplitDepths previousSplits_;  // cascades 0: none
  // Kept from frame to frame, so a steady-state frame allocates nothing (DESIGN §9).
  // receivers_: the visible set's boxes (B, thesis §9.2.1); receiverSelects_: per box, whether its
  // object showed in the read-back (the caster selection's receivers); sliceReceivers_: the slice's
  // boxes that select.
  std::vector<Aabb> receivers_, sliceReceivers_, footprints_;
  std::vector<std::uint8_t> receiverSelects_;
  std::vector<std::int32_t> frontier_, nextFrontier_;           // selectByHierarchy's top nodes
  std::vector<std::vector<std::int32_t>> partStacks_;           // per thread: its walk's stack
  std::vector<std::vector<std::uint32_t>> partCasters_;         // per thread: the casters it found
  std::vector<std::uint8_t> treeKept_;                          // refineCasters: per caster, its mask test
  std::vector<terrain::CellSpan> cellRuns_;  // one terrain block's (refineCasters)
  std::vector<glm::dvec2> receiverDepths_;  // each receiver's eye-depth range
  shadows::CasterSelector selector_;
  std::array<shadows::ReceiverMask, shadows::kMaxCascades> masks_;  // per slice (ShadowSlice::receiverMask)
  std::vector<shadows::ReceiverMask> bandMasks_;  // [1, bands): the other bands' masks (fillReceiverMask)
  std::vector<std::vector<float>> bandRows_;      // per band: a row's receiver depths (fillReceiverMask)
  WorkerThreads& workers_;                        // the bands' threads; the caster selection's
};

}  // namespace forest::render
