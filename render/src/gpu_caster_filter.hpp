#pragma once
// Shadow casters selected on the GPU without reading the G-buffer back (CasterSelection::
// ReceiverMaskGpu; Bittner, Mattausch, Silvennoinen & Wimmer, "Shadow Caster Culling for Efficient
// Shadow Mapping", I3D 2011, §4): per slice, a compute pass scatters the frame's sun-facing
// G-buffer pixels into a receiver mask over the slice's map — per texel the map depth of its
// farthest receiver, with a pyramid of maxima above it (shaders/receiver_mask.comp,
// receiver_mask_reduce.comp) — and the trees the CPU chose from the receivers' boxes are then
// tested instance by instance against it (shaders/caster_filter.comp): a tree stays when one of
// its height slabs, in the map and grown by what the lookups read, covers a texel whose farthest
// receiver lies beyond the slab's nearest point. Those that stay are compacted, per (species,
// LOD) group, into an instance buffer the shadow pass draws by glDrawElementsIndirect. The same
// test as the read-back mask (shadows::ReceiverMask) at texel resolution with box casters: exact
// (the term equals the term of all casters). Nothing is read back in a frame: the selected
// trees and their count are read only when asked (tests, the truth, statistics).
// Beyond the paper's mask, casters hidden from the light (with an object-ID layer beside the map):
// the trees whose fragments a receiver's lookup read in the last frame's map are drawn first
// (phase 1); a pyramid of the map's largest depths is built from them and the terrain
// (shaders/occluder_depths.comp), and every other tree is kept only when one of its slabs may come
// nearer the light than that at a texel it covers (phase 2) — a tree behind the canopy from the
// sun writes no texel, so the map is the same texel for texel. Which trees counted
// (shaders/caster_contribution.comp) decides how many are drawn, never the map.
#include <glm/glm.hpp>

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "forest/core/camera.hpp"
#include "forest/gl/objects.hpp"
#include "forest/gl/shader.hpp"
#include "forest/shadows/shadow_setup.hpp"
#include "forest/vegetation/forest.hpp"

namespace forest::render {

class GpuCasterFilter {
 public:
  static constexpr int kMaxSlices = 4, kMaxGroups = 32, kMaxDraws = 64;  // draws: tree draws a frame
  // `treeIdBase`: the object ID of tree 0 (SceneObjects::treeIdBase), as the instances carry it.
  GpuCasterFilter(const vegetation::Forest& forest, std::uint32_t treeIdBase);

  // A new frame: the slices' selections start empty. `occlusion`: the trees hidden from the light
  // are culled (the shadow pass gives an ID layer with each mask).
  void beginFrame(bool occlusion);
  // The receiver mask of slice `slice`: the sun-facing pixels of `surface` (the G-buffer surface,
  // gbuffer.frag) at eye depths [zMin, zMax], in the slice's map of mapSize² texels; `eye` is the
  // draws' view origin (DrawView::origin, the camera's position). Later filters test against it.
  // `map`: the shadow map (a layer per slice) the slice's draws go into; `ids`: its object-ID layers,
  // with occlusion (null without).
  void buildMask(int slice, const gl::Texture& surface, const Camera& camera, double zMin, double zMax,
                 const shadows::ShadowSetup& setup, const glm::dvec3& eye, const gl::Texture& map, const gl::Texture* ids,
                 double reachTexels);
  bool occlusion() const { return occlusion_ && ids_ != nullptr; }
  // Phase::Counted and Phase::Others with occlusion (the occluders built between them), All without.
  enum class Phase { All = 0, Counted = 1, Others = 2 };
  // The pyramid of the slice's map as drawn so far (phase 1 and the terrain), for Phase::Others.
  void buildOccluders();
  // After the slice's draws: marks the trees its receivers' lookups read (the next frame's phase 1).
  void markCounted();

  // One group of a tree draw's instances (all of one species and LOD, consecutive in the input).
  struct Group {
    std::uint32_t first = 0, count = 0;  // instances, relative to the draw's base instance
    int species = 0;
    std::uint32_t indexCount = 0, firstIndex = 0;
    int baseVertex = 0;
  };
  // Tests the draw's instances (TreeRenderer::InstanceGpu records from `baseInstance` in buffer
  // `instances`) against the current slice's mask and writes what stays; the draw then reads
  // instances from output() and issues, for group g, the indirect command at byte offset
  // returned + g · commandBytes() of commands().
  std::size_t select(GLuint instances, std::uint32_t baseInstance, std::span<const Group> groups, Phase phase = Phase::All);
  GLuint output() const { return output_.id(); }
  GLuint commands() const { return commands_.id(); }
  static std::size_t commandBytes() { return sizeof(Command); }

  // Read back (waits for the GPU): the object IDs the slice's draws kept, and the triangles they drew.
  std::vector<std::uint32_t> selectedIds(int slice) const;
  std::uint32_t selectedCount(int slice) const;
  long long selectedTriangles(int slice) const;

 private:
  struct Command {  // glDrawElementsIndirect's
    std::uint32_t count, instanceCount, firstIndex;
    std::int32_t baseVertex;
    std::uint32_t baseInstance;
  };
  struct Params;  // caster_filter.comp's Params block (gpu_caster_filter.cpp)
  void ensureMask(int mapSize);
  void setCommonUniforms(const gl::Program& program) const;  // the mask's map and pyramid
  void ensureOutput(std::size_t instances);

  const vegetation::Forest& forest_;
  std::uint32_t treeIdBase_;
  std::array<glm::vec4, 4 * vegetation::kCasterSlabs> slabs_{};  // Params::slabs, per species and slab
  gl::Program build_, reduce_, reach_program_, filter_, occludersFromMap_, occludersReduce_, markCounted_;
  gl::Texture mask_;       // R32UI, a pyramid of levels
  gl::Texture reads_, readsAlongX_;  // R32UI: per texel the farthest receiver whose lookup may read it
  gl::Texture occluders_;  // R32F, level 0 the map's depths, a pyramid of maxima
  int mapSize_ = 0, levels_ = 0;  // the occluders' pyramid has the mask's levels
  gl::Buffer counted_;     // per tree: the frame it last counted in (contributedIn)
  std::uint32_t frame_ = 0, lastFrame_ = 0;  // this frame's number; the last one that marked (0: none)
  bool occlusion_ = false, marked_ = false;
  const gl::Texture* map_ = nullptr;
  const gl::Texture* ids_ = nullptr;
  gl::Buffer flags_, params_, commands_, output_;
  std::array<gl::Buffer, kMaxSlices> selection_;  // per slice: the count, then the kept object IDs
  // The current slice and its mask's map (set by buildMask).
  int slice_ = 0;
  glm::mat4 toClip_{1.0f}, fromClip_{1.0f};  // (p − eye) → the map's clip coordinates, and back
  glm::vec4 lightDepthRow_{0.0f};
  bool linearDepth_ = false;
  float reach_ = 0.0f;
  std::uint32_t outputUsed_ = 0;  // instances written into output_ this frame
  int draws_ = 0;                 // tree draws this frame: a block of kMaxGroups commands each
  std::array<std::vector<int>, kMaxSlices> sliceDraws_;  // the blocks of each slice's draws
};

}  // namespace forest::render
