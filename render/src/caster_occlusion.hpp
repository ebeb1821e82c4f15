#pragma once
// Trees hidden from the sun, culled on the read-back path (CasterSelection::ReceiverPixels): the
// CPU's form of what the GPU's caster filter does beside its mask (gpu_caster_filter.hpp). The
// trees whose texels a receiver's lookup read in the last frame's map are drawn first with the
// terrain and every other caster; the layer is read back; each other tree is then drawn only where
// one of its crown slabs (vegetation/crown_slabs.hpp) may come nearer the light than the layer
// holds at a texel centre it covers — where the light's line through that centre enters the slab —
// and a receiver beyond that point reads the texel (shadows::ReceiverMask::farthestReading). A
// tree behind the canopy from the sun writes no texel a lookup reads, so the term is the term of
// all casters, whatever the last frame was; which trees counted decides only how many are drawn.
#include <cstdint>
#include <span>
#include <vector>

#include "forest/core/max_pyramid.hpp"
#include "forest/render/scene_objects.hpp"
#include "forest/render/tree_renderer.hpp"
#include "forest/shadows/receiver_mask.hpp"
#include "forest/shadows/shadow_setup.hpp"
#include "worker_threads.hpp"

namespace forest::render {

class CasterOcclusion {
 public:
  // `workers` share out keepUnhidden's trees (the rasteriser waits meanwhile: its layer was read back).
  CasterOcclusion(const SceneObjects& objects, WorkerThreads& workers);
  // A new frame: the trees marked in the last one count.
  void beginFrame();
  // Whether culling pays on a layer (HiddenCasters::Auto): the triangles it is expected to leave out
  // — those of the trees that did not count, at the eye's LODs, times the share it left out when it
  // last culled — against its two read-backs of `texels` and its test of each tree that did not
  // count, in the time each took when it last culled (measuredCosts; before that, the test free).
  // A layer not culled lets that share grow back by a tenth a frame, so a view that changes is
  // tried again.
  // `impostors`: the switch the trees are drawn with (a tree beyond it costs its impostor's quad).
  bool worthCulling(std::span<const std::uint32_t> casters, long long texels, const glm::dvec3& eye, const ImpostorSwitch& impostors);
  // The wall time of the last culled layer's draw of the trees kept (`drawMs`, ending in a
  // read-back, so the GPU's work is in it) over their triangles at the eye's LODs, and of
  // keepUnhidden's test per tree (timed there): worthCulling's prices from then on.
  void measuredCosts(double drawMs, std::span<const std::uint32_t> drawn, const glm::dvec3& eye, const ImpostorSwitch& impostors);
  // Splits `casters` (object indices) into what is drawn first — everything but the trees that did
  // not count in the last frame — and those trees.
  void split(std::span<const std::uint32_t> casters, std::vector<std::uint32_t>& first, std::vector<std::uint32_t>& others) const;
  // Keeps of `trees` (object indices) those that may lower a texel a receiver of `mask` reads, the
  // layer holding `depths` (as stored, [0, 1], row by row over `rect`) in the slice's map of
  // mapSize² texels with `setup`; `reachTexels`: how far a lookup reads from its point.
  // `eye`: the draws' LOD origin (what the share left out is weighed by).
  void keepUnhidden(const shadows::ShadowSetup& setup, int mapSize, const shadows::ReceiverMask& mask, double reachTexels,
                    const shadows::TexelRect& rect, std::span<const float> depths, const glm::dvec3& eye,
                    const ImpostorSwitch& impostors, std::vector<std::uint32_t>& trees);
  // Marks the trees whose object IDs (`ids`, row by row over `rect`) lie at texels a receiver of
  // `mask` reads: the next frame draws them first.
  void markCounted(const shadows::ReceiverMask& mask, double reachTexels, const shadows::TexelRect& rect,
                   std::span<const std::uint32_t> ids);

 private:
  // What the tree's draw submits at the eye: its LOD's triangles, beyond the switch its impostor's
  // quad instead, in the cross-fade band both (TreeRenderer's choice).
  long long triangles(std::uint32_t tree, const glm::dvec3& eye, const ImpostorSwitch& impostors) const;
  // The tree's crown slabs …
  // … all at or beyond the largest depth the layer holds over their footprint (heldDepths_): a
  // conservative test in constant time that decides most hidden trees before treeMayShow.
  bool hiddenByHeldDepths(std::span<const vegetation::PlacedCrownSlab> slabs, const shadows::ShadowSetup& setup, int mapSize,
                          const shadows::TexelRect& rect) const;
  bool slabBehindHeldDepths(const Aabb& grown, const shadows::ShadowSetup& setup, const shadows::TexelRect& rect, int x0, int y0, int x1,
                            int y1) const;
  bool notNearerThanHeld(double nearest, const shadows::TexelRect& rect, int x0, int y0, int x1, int y1) const;
  // … may lower a texel of the layer that a receiver beyond them reads (the exact test).
  bool treeMayShow(std::span<const vegetation::PlacedCrownSlab> slabs, const shadows::ShadowSetup& setup, int mapSize,
                   const shadows::ReceiverMask& mask, double reachTexels, const shadows::TexelRect& rect, std::span<const float> depths) const;

  const SceneObjects& objects_;
  std::vector<std::uint8_t> counted_, marked_;  // per tree: counted in the last frame, marked in this one
  glm::dmat4 clipToWorld_{1.0};                 // the slice's, for keepUnhidden
  double culledShare_ = 1.0;                    // of the tested trees' triangles, left out when last culled
  double msPerTestedTree_ = 0.0, msPerTriangle_ = 0.0;  // measured when last culled (0: not yet)
  double lastTestMs_ = 0.0;
  std::size_t lastTested_ = 0;
  WorkerThreads& workers_;
  std::vector<std::vector<vegetation::PlacedCrownSlab>> slabs_;  // per part: one tree's
  std::vector<long long> tested_, culled_;                        // per part: triangles tested, culled
  std::vector<std::uint8_t> keep_;                               // per tree tested: it may show
  MaxPyramid heldDepths_;                           // the layer's depths read back, over the rectangle drawn
};

}  // namespace forest::render
