#pragma once
// Draws the forest's trees (module vegetation/): one vertex and index buffer holding every LOD of
// every species, a per-frame stream of instances grouped by (species, LOD), and one instanced
// draw per group — at most 6 draws however many trees are visible. trees.vert applies the
// same transform as Forest::treeTransform (scale, yaw, wind shear, camera-relative position).
#include <array>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "forest/core/camera.hpp"
#include "forest/core/scene.hpp"
#include "forest/gl/objects.hpp"
#include "forest/gl/stream_ring.hpp"
#include "forest/gl/uniform_stream.hpp"
#include "forest/gl/shader.hpp"
#include "forest/render/draw_view.hpp"
#include "forest/vegetation/forest.hpp"

namespace forest::render {

class GpuCasterFilter;  // render/src/gpu_caster_filter.hpp

class TreeRenderer {
 public:
  // Lit: Lambert + ambient with per-tree tint. ObjectId: objectIdBase + tree index to a GL_R32UI
  // colour target. GBuffer: the geometry pass's outputs.
  using Output = SurfaceOutput;

  TreeRenderer(const vegetation::Forest& forest, Output output = Output::Lit, std::uint32_t objectIdBase = 1);

  struct Stats {
    int trees = 0;
    long long triangles = 0;
    std::array<int, vegetation::kTreeLods> treesPerLod{};
    int draws = 0;
  };
  // Draws `trees` (indices into Forest::trees(), each once) at `time`, each at the LOD the eye's
  // distance gives it.
  Stats draw(const Camera& camera, std::span<const std::uint32_t> trees, double time, const SunSettings& sun) const;
  // The same from any view (LOD from view.lodEye).
  Stats draw(const DrawView& view, std::span<const std::uint32_t> trees) const;
  // Occlusion queries drawn with the trees' own triangles (culling::ObjectDrawer's geometry
  // queries): trees[i] exactly as draw() places it, each passing fragment writing the culler's
  // stamp into result slot slots[i] (SurfaceOutput::QueryStamp) — or, with `hulls` and for a
  // species with a query hull (vegetation::SpeciesModel::queryHull), its hull under the same
  // transform, which holds every LOD. The caller sets the depth test and masks and binds the
  // culler's block and buffer.
  Stats drawQueries(const DrawView& view, std::span<const std::uint32_t> trees, std::span<const std::uint32_t> slots,
                    bool hulls = true) const;
  // With a filter, draw() hands each draw's instances to it (the shadow pass's casters selected on
  // the GPU, CasterSelection::ReceiverMaskGpu) and draws what it keeps by indirect draws; null:
  // every tree given is drawn. Stats then count the trees given, not those kept, and no triangles
  // (GpuCasterFilter::selectedTriangles reads what was drawn back).
  void setCasterFilter(GpuCasterFilter* filter) { filter_ = filter; }
  // Trees whose boxes meet the camera's frustum.
  std::vector<std::uint32_t> treesInFrustum(const Camera& camera) const;

  std::size_t meshBytes() const { return vertices_.size() + indices_.size(); }
  std::size_t instanceBytes() const { return instances_->size(); }

 private:
  // What the vertex shader needs of a tree, worked out per draw in double on the CPU, so that no
  // vertex evaluates a sine (llvmpipe shades vertices on the thread that issues the draws).
  struct InstanceGpu {
    glm::vec4 baseScale;      // base − view origin; scale
    glm::vec4 rotationShear;  // cos yaw, sin yaw; the wind's shear at the draw's time (x, z)
    glm::vec4 tint;
    std::uint32_t objectId;
    std::uint32_t padding[3];
  };
  struct Range {
    int baseVertex = 0, firstIndex = 0, indexCount = 0;
  };
  // The instances of `trees` written into the ring, grouped by (species, LOD): each group's count
  // and first instance (relative to baseInstance). Each instance's ID is ids[i], or
  // objectIdBase + tree without ids.
  static constexpr int kGroups = vegetation::kSpeciesCount * vegetation::kTreeLods;
  struct Groups {
    std::array<int, kGroups> counts{}, first{};
    GLuint baseInstance = 0;
    bool empty = true;
  };
  Groups writeInstances(const DrawView& view, std::span<const std::uint32_t> trees, std::span<const std::uint32_t> ids) const;
  // The groups' triangles drawn with the filter (filter_): indirect draws of what it kept.
  Stats drawFiltered(const DrawView& view, const Groups& groups) const;
  // Draws the trees with `program`; each instance's ID is ids[i], or objectIdBase + tree without ids.
  // `hulls`: a species with a query hull is drawn with it at every LOD.
  Stats drawInstances(const DrawView& view, std::span<const std::uint32_t> trees, std::span<const std::uint32_t> ids,
                      const gl::Program& program, bool hulls = false) const;
  const vegetation::Forest& forest_;
  Output output_;
  std::uint32_t objectIdBase_;
  gl::Program program_;
  mutable std::optional<gl::Program> queryProgram_;  // SurfaceOutput::QueryStamp, loaded at the first query
  mutable gl::UniformStream viewUniforms_;  // ViewBlock at binding 0
  gl::VertexArray vertexArray_;
  gl::Buffer vertices_, indices_;
  // Instances, written once per draw into a persistently mapped ring (DESIGN §9): each draw
  // addresses its part by base instance; nothing the GPU may still read is rewritten.
  std::unique_ptr<gl::StreamRing> instances_;
  // Per-draw scratch: each drawn tree's (species, LOD) group, room for every tree (no allocation).
  mutable std::vector<std::uint8_t> groupOf_;
  std::array<std::array<Range, vegetation::kTreeLods>, vegetation::kSpeciesCount> ranges_{};
  std::array<Range, vegetation::kSpeciesCount> hullRanges_{};  // indexCount 0: no query hull
  GpuCasterFilter* filter_ = nullptr;
};

}  // namespace forest::render
