#pragma once
// Pass 3 of the frame (thesis §5.1, §9.3): the selected casters only, front faces culled
// (backside rendering), into a float depth map — one layer of an array texture per slice of the
// plan (cascades) — drawn at the eye's LOD; tsm writes the linear light depth (TSM §4).
#include <memory>
#include <optional>
#include <vector>

#include "forest/gl/objects.hpp"
#include "forest/render/frame.hpp"
#include "forest/render/scene_objects.hpp"
#include "gpu_caster_filter.hpp"
#include "shadow_setup_pass.hpp"
#include "caster_occlusion.hpp"
#include "slice_cache.hpp"

namespace forest::render {

// (p − eye) → shadow clip with z in [0, 1] (the engine's zero-to-one clip control), in double.
glm::dmat4 eyeRelativeToShadowClip(const shadows::ShadowSetup& setup, const glm::dvec3& eye);

class ShadowPass {
 public:
  // `workers`: the CPU's threads (the read-back path's hidden-caster test).
  ShadowPass(const SceneObjects& objects, const terrain::Terrain* terrain, const vegetation::Forest* forest,
             const std::vector<PropBox>& props, WorkerThreads& workers);

  // Clears each slice's layer (to the far depth) and draws its casters when the plan is shadowed.
  // Returns the triangles drawn; each slice's triangles (and, with Profiling timing, its time) go
  // into stats.cascade. `receiverSurface`: the G-buffer surface, for CasterSelection::ReceiverMaskGpu
  // (each slice's trees are tested on the GPU against its receivers; null otherwise).
  long long run(const ShadowPlan& plan, const DrawView& eye, const terrain::TerrainLod* lod, const FrameSettings& settings,
                const glm::dvec3& l, const gl::Texture* receiverSurface, FrameStats& stats);
  // The trees drawn into a slice's layer in the last frame when they were tested beyond the
  // selection — on the GPU (read back: waits for the pass) or against the layer read back
  // (CasterOcclusion) — as object indices, increasing; else nullopt.
  std::optional<std::vector<std::uint32_t>> treesTested(int slice) const;
  void propsMoved(const std::vector<PropBox>& props);
  // Trees moved (Frame::moveTrees): no cached layer holds them where they are.
  void treesMoved() { cache_.forget(); }
  // Far trees as impostors from here on (TreeRenderer::setImpostors), in every tree renderer.
  void setImpostors(const ImpostorAtlas* atlas, const ImpostorSwitch& impostors);

  const gl::Texture& map() const { return map_; }  // a 2D array texture, one layer per slice
  int size() const { return size_; }
  int layers() const { return layers_; }

 private:
  void ensureMap(int size, int layers);
  // Clears layer i (a Redraw) and draws `layer`'s casters into it (into its rectangle when scissored): the
  // triangles drawn (with the GPU's filter and Profiling timing, the trees it kept included).
  long long drawLayer(int i, const ShadowPlan& plan, const ShadowSlice& slice, const LayerDraw& layer, bool scissored,
                      const DrawView& eye, const terrain::TerrainLod* lod, const FrameSettings& settings, const glm::dvec3& l,
                      const gl::Texture* receiverSurface, FrameStats& stats);
  // Returns the triangles drawn; adds the terrain's to `terrainTriangles`.
  long long drawSlice(const ShadowSlice& slice, const LayerDraw& layer, const DrawView& eye, const terrain::TerrainLod* lod,
                      const FrameSettings& settings, const glm::dvec3& l, long long& terrainTriangles);
  // The slice's terrain casters: its blocks, or its tiles whole.
  long long drawTerrain(const TerrainRenderer& renderer, const ShadowSlice& slice, const LayerDraw& layer,
                        const DrawView& light, const terrain::TerrainLod& lod);
  void ensureLightDepthRenderers();  // the TSM renderers, built on first use
  // The GPU's caster filter on the tree renderers for this frame (null: none), built on first use.
  void useGpuFilter(bool use);
  void ensureIdLayers();
  // The slice's casters in two draws with the trees hidden from the sun culled between them
  // (CasterOcclusion): what the layer holds after the first is read back. `reach`: how far a lookup
  // reads (ShadowPlan::lookupReachTexels). The triangles drawn.
  long long drawWithOcclusion(int i, const ShadowSlice& slice, const LayerDraw& layer, double reach, const DrawView& eye, const terrain::TerrainLod* lod,
                              const FrameSettings& settings, const glm::dvec3& l, FrameStats& stats);
  int countOtherThanTrees(std::span<const std::uint32_t> casters) const;  // the tiles and props among them

  const SceneObjects& objects_;
  WorkerThreads& workers_;
  const terrain::Terrain* terrainSource_;
  const vegetation::Forest* forestSource_;
  const std::vector<PropBox>& propsSource_;  // the scene's, moved by the caller
  std::unique_ptr<TerrainRenderer> terrain_, terrainLightDepth_;
  std::unique_ptr<TreeRenderer> trees_, treesLightDepth_;
  const ImpostorAtlas* impostorAtlas_ = nullptr;
  ImpostorSwitch impostors_;
  // The switch the trees are drawn with (none without an atlas: TreeRenderer draws meshes then).
  ImpostorSwitch drawnImpostors() const { return impostorAtlas_ ? impostors_ : ImpostorSwitch{}; }
  std::unique_ptr<PropRenderer> props_, propsLightDepth_;
  // Trees and props; the terrain is drawn apart, by tile or by block (ShadowSlice::terrainByBlock).
  std::unique_ptr<SceneDrawer> drawer_, lightDepthDrawer_;  // kept: their lists are reused
  std::vector<int> tiles_;  // scratch: the caster tiles of a slice drawn whole
  std::unique_ptr<GpuCasterFilter> gpuFilter_;
  bool filteredOnGpu_ = false;  // the last run tested its trees on the GPU
  std::unique_ptr<CasterOcclusion> occlusion_;  // the read-back path's (built on first use)
  std::array<std::optional<std::vector<std::uint32_t>>, shadows::kMaxCascades> treesOccluded_;  // per slice: the trees drawn, when culled
  std::vector<std::uint32_t> first_, others_, idsRead_;  // drawWithOcclusion's
  std::vector<float> depthsRead_;
  gl::Texture map_;
  std::vector<gl::Framebuffer> framebuffers_;  // one per layer
  gl::Texture ids_;                               // object IDs beside the map, for the GPU's caster filter
  std::vector<gl::Framebuffer> idFramebuffers_;   // a layer of the map and of ids_ each
  GLuint idsBesideMap_ = 0;                       // the map they were made for
  int size_ = 0, layers_ = 0;
  SliceCache cache_;  // what each layer holds (FrameSettings::cacheSlices)
};

}  // namespace forest::render
