#pragma once
// Pass 1 of the frame (DESIGN §1): the culling traversal draws the G-buffer — eye depth, albedo with
// whether the drawn triangle faces the sun, shading normal, object ID; reversed-Z depth — and returns
// the visible set with its z_f.
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "forest/culling/bvh.hpp"
#include "forest/culling/occlusion_culler.hpp"
#include "forest/gl/objects.hpp"
#include "forest/render/scene_objects.hpp"

namespace forest::render {

// The geometry pass's targets, read by the shadow term and the lighting: the surface, one RGBA32UI
// texel per pixel (shaders/gbuffer.frag has its layout: eye depth, albedo with whether the drawn
// triangle's plane faces the sun — all that the shadow term and the receiver pixels need of that
// normal —, the shading normal, the object ID), and the reversed-Z depth. One texel, so that a
// full-screen pass fetches each pixel once: on llvmpipe each texel fetch of a full-screen pass at
// 800×600 costs ~1.3 ms, and each colour target costs the geometry pass (a fourth one, the
// geometric normal as RGBA16F, made it ~17% slower).
struct GBuffer {
  GBuffer(int width, int height);
  gl::Texture surface, depth;
  gl::Framebuffer framebuffer;
};

class GeometryPass {
 public:
  GeometryPass(const SceneObjects& objects, const terrain::Terrain* terrain, const vegetation::Forest* forest,
               const std::vector<PropBox>& props, int width, int height, const CullingSettings& culling);

  // Clears the G-buffer and draws what the culler finds visible; with `frozen`, exactly those
  // objects, without culling (FrameSettings::freezeCulling). With an occlusion strategy and
  // [culling] terrain_blocks, a drawn tile draws its visible blocks (TerrainBlockVisibility); the
  // result's stats count the blocks' queries and triangles. The result is valid until the next run
  // (the culler's or this pass's storage, reused).
  const culling::CullingResult& run(const Camera& camera, const DrawView& eye, const terrain::TerrainLod* lod,
                             culling::CullingStrategy strategy, culling::OcclusionCuller& culler, const culling::Bvh& bvh,
                             const std::vector<std::uint32_t>* frozen);
  void propsMoved(const std::vector<PropBox>& props) { props_->update(props); }
  // Far trees as impostors from here on (TreeRenderer::setImpostors).
  void setImpostors(const ImpostorAtlas* atlas, const ImpostorSwitch& impostors) {
    if (trees_) trees_->setImpostors(atlas, impostors);
  }
  // The blocks with a pixel in the last frame's image, for the next run only
  // (TerrainBlockVisibility::setShownInLastImage).
  void setShownBlocksInLastImage(std::span<const std::uint16_t> shown) {
    if (blockVisibility_) blockVisibility_->setShownInLastImage(shown);
  }
  // Forgets which terrain blocks were visible (a camera cut).
  void resetHistory() {
    if (blockVisibility_) blockVisibility_->reset();
  }
  const GBuffer& gbuffer() const { return gbuffer_; }

 private:
  const SceneObjects& objects_;
  int width_, height_;
  GBuffer gbuffer_;
  std::unique_ptr<TerrainRenderer> terrain_;
  std::unique_ptr<TreeRenderer> trees_;
  std::unique_ptr<PropRenderer> props_;
  std::unique_ptr<SceneDrawer> drawer_;
  culling::CullingResult frozenResult_;
  std::optional<TerrainBlockVisibility> blockVisibility_;  // with terrain and [culling] terrain_blocks
  culling::CullingResult blockResult_;  // the culler's result with the late blocks' triangles
  std::optional<Frustum> frustum_;  // this frame's eye frustum: terrain blocks outside it are not drawn
};

}  // namespace forest::render
