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
  static constexpr int kMaxSlices = 4, kMaxGroups = 16, kMaxDraws = 64;  // draws: tree draws a frame
  explicit GpuCasterFilter(const vegetation::Forest& forest);

  // A new frame: the slices' selections start empty.
  void beginFrame();
  // The receiver mask of slice `slice`: the sun-facing pixels of `surface` (the G-buffer surface,
  // gbuffer.frag) at eye depths [zMin, zMax], in the slice's map of mapSize² texels; `eye` is the
  // draws' view origin (DrawView::origin, the camera's position). Later filters test against it.
  void buildMask(int slice, const gl::Texture& surface, const Camera& camera, double zMin, double zMax,
                 const shadows::ShadowSetup& setup, const glm::dvec3& eye, int mapSize, double reachTexels);

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
  std::size_t select(GLuint instances, std::uint32_t baseInstance, std::span<const Group> groups);
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
  void ensureOutput(std::size_t instances);

  const vegetation::Forest& forest_;
  gl::Program build_, reduce_, filter_;
  gl::Texture mask_;  // R32UI, a pyramid of levels
  int mapSize_ = 0, levels_ = 0;
  gl::Buffer flags_, params_, commands_, output_;
  std::array<gl::Buffer, kMaxSlices> selection_;  // per slice: the count, then the kept object IDs
  // The current slice and its mask's map (set by buildMask).
  int slice_ = 0;
  glm::mat4 toClip_{1.0f};
  glm::vec4 lightDepthRow_{0.0f};
  bool linearDepth_ = false;
  float reach_ = 0.0f;
  std::uint32_t outputUsed_ = 0;  // instances written into output_ this frame
  int draws_ = 0;                 // tree draws this frame: a block of kMaxGroups commands each
  std::array<std::vector<int>, kMaxSlices> sliceDraws_;  // the blocks of each slice's draws
};

}  // namespace forest::render
