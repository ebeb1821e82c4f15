#pragma once
// Visibility culling over a BVH with hardware occlusion queries (DESIGN §4 culling/):
//   none          — draw every object;
//   frustum       — view-frustum culling of the hierarchy;
//   stop-and-wait — front to back, query each node in the frustum and wait for its result;
//   chc           — coherent hierarchical culling (Bittner, Wimmer, Piringer, Purgathofer,
//                   EG 2004): previously visible leaves are drawn at once and queried for the next
//                   frame, previously visible interior nodes are opened without a query, previously
//                   invisible nodes are queried and opened only when their result says visible;
//                   traversal continues while results are pending (results are taken in batches
//                   at fixed traversal steps, so every run traverses alike), a visible result
//                   pulls visibility up to the root.
// A query tests the node's box (grown by a few ulps) against the depth of what has been drawn so
// far, which only gets nearer as more is drawn: a box found hidden holds nothing visible, so the
// geometry pass equals drawing everything (exactness). Boxes holding the eye (grown by z_n) or
// crossing the near plane count as visible without a query.
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "forest/core/bounds.hpp"
#include "forest/core/camera.hpp"
#include "forest/culling/bvh.hpp"
#include "forest/gl/objects.hpp"
#include "forest/gl/shader.hpp"

namespace forest::culling {

enum class CullingStrategy { None, Frustum, StopAndWait, Chc };
CullingStrategy parseCullingStrategy(std::string_view name);  // throws InputError
std::string_view cullingStrategyName(CullingStrategy strategy);

// What the renderer implements: draw these objects (indices into the BVH's object boxes) into the
// bound framebuffer with the pass's state; return the triangles drawn.
class ObjectDrawer {
 public:
  virtual ~ObjectDrawer() = default;
  virtual long long draw(std::span<const std::uint32_t> objects) = 0;
};

struct CullingStats {
  int nodesVisited = 0;      // nodes taken from the traversal queue inside the frustum
  int queriesIssued = 0;
  int objectsDrawn = 0;
  long long trianglesDrawn = 0;
  double waitMilliseconds = 0.0;  // CPU time blocked on query results
};

struct CullingResult {
  std::vector<std::uint32_t> visibleObjects;  // sorted; a superset of the objects with a visible pixel
  double farDepth = 0.0;                      // z_f: largest eye depth of the visible boxes, in [near, far]
  CullingStats stats;
};

// z_f of a set of objects: the largest eye depth of their boxes, clamped to [near, far] (near
// for an empty set).
double farDepthOf(std::span<const std::uint32_t> objects, std::span<const Aabb> objectBoxes, const Camera& camera);

class OcclusionCuller {
 public:
  OcclusionCuller();  // needs a current GL context

  // One frame. `objectBoxes[i]` is object i's box (the BVH was built over them). The framebuffer
  // the pass draws into must be bound and cleared; depth test GL_GREATER (reversed-Z).
  CullingResult cull(const Bvh& bvh, std::span<const Aabb> objectBoxes, const Camera& camera, CullingStrategy strategy,
                     ObjectDrawer& drawer);
  // Forgets the previous frame's visibility (after a BVH rebuild or a camera cut).
  void reset();

 private:
  struct NodeState {
    bool visible = false;
    std::uint64_t lastVisited = 0;
  };
  // Issues a query for a node's box; returns its slot in the pool.
  std::size_t issueQuery(const Aabb& box);
  std::uint32_t waitResult(std::size_t slot, CullingStats& stats) const;
  void beginQueries();
  void endQueries();

  gl::Program program_;
  gl::VertexArray vertexArray_;
  gl::Buffer cube_;
  gl::Buffer cubeIndices_;
  std::vector<gl::Query> pool_;
  std::size_t used_ = 0;
  glm::dvec3 eye_{0.0};
  glm::dmat4 viewProjectionRelative_{1.0};
  bool queryState_ = false;

  std::vector<NodeState> state_;
  const Bvh* stateOf_ = nullptr;
  std::uint64_t frame_ = 0;
};

}  // namespace forest::culling
