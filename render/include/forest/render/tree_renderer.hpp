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
class ImpostorAtlas;    // forest/render/impostor_atlas.hpp

// Where a tree is drawn as its impostor (issue "Far trees as impostors"): beyond `distance` metres
// from the LOD eye to its base, divided by its size class's scale (as the LOD bands), it fades from
// its mesh to its impostor over `band` × distance, dithered (shaders/impostor.glsl); beyond that it
// is its impostor alone. distance 0: every tree is a mesh.
constexpr long long kImpostorTriangles = 2;  // an impostor is one quad (impostor.vert)

struct ImpostorSwitch {
  double distance = 0.0;
  double band = 0.1;
};
// The share of the tree's pixels its impostor draws at `eyeDistance` (metres, already divided by
// the size class's scale): 0 (all mesh) to 1 (all impostor).
double impostorShare(const ImpostorSwitch& impostors, double eyeDistance);

class TreeRenderer {
 public:
  // Lit: Lambert + ambient with per-tree tint. ObjectId: objectIdBase + tree index to a GL_R32UI
  // colour target. GBuffer: the geometry pass's outputs.
  using Output = SurfaceOutput;

  TreeRenderer(const vegetation::Forest& forest, Output output = Output::Lit, std::uint32_t objectIdBase = 1);

  struct Stats {
    int trees = 0;
    long long triangles = 0;
    std::array<int, vegetation::kTreeLods> treesPerLod{};  // drawn by their meshes (in full or fading)
    int impostors = 0;                                     // drawn by their impostors (in full or fading)
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
  // Far trees as impostors from `atlas` (null, or a switch at distance 0: meshes only). The atlas
  // must outlive the draws.
  void setImpostors(const ImpostorAtlas* atlas, const ImpostorSwitch& impostors);
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
    std::uint32_t fadeBits;  // float: the impostor's share of the cross-fade (impostor.glsl), 1 outside it
    std::uint32_t species;   // the impostor's layer and volumes
    std::uint32_t padding;
  };
  struct Range {
    int baseVertex = 0, firstIndex = 0, indexCount = 0;
  };
  // How a group draws its trees: a LOD's mesh in full, a LOD's mesh cross-fading with the impostor
  // (its pixels where the impostor leaves them), or the impostor.
  static constexpr int kRepresentations = 2 * vegetation::kTreeLods + 1;
  static constexpr int kImpostor = 2 * vegetation::kTreeLods;
  // The instances of `trees` written into the ring, grouped by (species, representation): each
  // group's count and first instance (relative to baseInstance); a tree in the cross-fade is in two
  // groups. Each instance's ID is ids[i], or objectIdBase + tree without ids.
  static constexpr int kGroups = vegetation::kSpeciesCount * kRepresentations;
  struct Groups {
    std::array<int, kGroups> counts{}, first{};
    GLuint baseInstance = 0;
    bool empty = true;
  };
  Groups writeInstances(const DrawView& view, std::span<const std::uint32_t> trees, std::span<const std::uint32_t> ids) const;
  // The groups' triangles drawn with the filter (filter_): indirect draws of what it kept.
  Stats drawFiltered(const DrawView& view, const Groups& groups, std::size_t trees) const;
  // Draws the trees; each instance's ID is ids[i], or objectIdBase + tree without ids. `query`: the
  // geometry queries' programs (SurfaceOutput::QueryStamp), and with `hulls` a species with a query
  // hull is drawn with it in place of its meshes.
  Stats drawInstances(const DrawView& view, std::span<const std::uint32_t> trees, std::span<const std::uint32_t> ids,
                      bool query, bool hulls = false) const;
  // The program and the index range a representation of a species draws with.
  const gl::Program& programFor(int representation, bool query) const;
  const Range& rangeFor(int species, int representation, bool hull) const;
  // Before and after a group of impostors: their atlas and block bound, face culling off (the quad
  // faces the viewer; a backside shadow pass culls front faces); then the culling as it was.
  void beginImpostors() const;
  void endImpostors() const;
  const vegetation::Forest& forest_;
  Output output_;
  std::uint32_t objectIdBase_;
  gl::Program program_;
  mutable std::optional<gl::Program> queryProgram_;  // SurfaceOutput::QueryStamp, loaded at the first query
  // The cross-fading meshes' and the impostors' programs (and their queries), loaded at first use.
  mutable std::optional<gl::Program> fadingProgram_, fadingQueryProgram_, impostorProgram_, impostorQueryProgram_;
  const ImpostorAtlas* atlas_ = nullptr;
  ImpostorSwitch impostors_;
  mutable bool cullingWasOn_ = true;
  mutable gl::UniformStream viewUniforms_;  // ViewBlock at binding 0
  gl::VertexArray vertexArray_;
  gl::Buffer vertices_, indices_;
  // Instances, written once per draw into a persistently mapped ring (DESIGN §9): each draw
  // addresses its part by base instance; nothing the GPU may still read is rewritten.
  std::unique_ptr<gl::StreamRing> instances_;
  // Per-draw scratch: each drawn tree's group (and the impostor's share where it cross-fades), room
  // for every tree (no allocation).
  mutable std::vector<std::uint8_t> groupOf_;
  mutable std::vector<float> fadeOf_;
  std::array<std::array<Range, vegetation::kTreeLods>, vegetation::kSpeciesCount> ranges_{};
  std::array<Range, vegetation::kSpeciesCount> hullRanges_{};  // indexCount 0: no query hull
  Range quadRange_;  // the impostor's quad: corners (±1, ±1, 0), counter-clockwise
  GpuCasterFilter* filter_ = nullptr;
};

}  // namespace forest::render
