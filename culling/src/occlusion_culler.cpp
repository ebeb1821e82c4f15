#include "forest/culling/occlusion_culler.hpp"

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <thread>

#include "forest/core/error.hpp"
#include "traversal.hpp"

namespace forest::culling {

using glm::dvec3;

double farDepthOf(std::span<const std::uint32_t> objects, std::span<const Aabb> objectBoxes, const Camera& camera) {
  const glm::dmat4 view = camera.view();
  double farDepth = camera.near;
  for (std::uint32_t o : objects) farDepth = std::max(farDepth, depthRange(objectBoxes[o], view).second);
  return std::min(farDepth, camera.far);
}

CullingStrategy parseCullingStrategy(std::string_view name) {
  if (name == "none") return CullingStrategy::None;
  if (name == "frustum") return CullingStrategy::Frustum;
  if (name == "stop-and-wait") return CullingStrategy::StopAndWait;
  if (name == "chc") return CullingStrategy::Chc;
  if (name == "chc++") return CullingStrategy::ChcPlusPlus;
  throw InputError(fmt::format("culling strategy '{}': expected none, frustum, stop-and-wait, chc or chc++", name));
}

std::string_view cullingStrategyName(CullingStrategy strategy) {
  switch (strategy) {
    case CullingStrategy::None: return "none";
    case CullingStrategy::Frustum: return "frustum";
    case CullingStrategy::StopAndWait: return "stop-and-wait";
    case CullingStrategy::Chc: return "chc";
    case CullingStrategy::ChcPlusPlus: return "chc++";
  }
  return "?";
}

std::vector<std::string> cullingStrategyNames() { return {"none", "frustum", "stop-and-wait", "chc", "chc++"}; }

QueryMode parseQueryMode(std::string_view name) {
  if (name == "deterministic") return QueryMode::Deterministic;
  if (name == "async") return QueryMode::Async;
  throw InputError(fmt::format("query mode '{}': expected deterministic or async", name));
}

std::string_view queryModeName(QueryMode mode) { return mode == QueryMode::Deterministic ? "deterministic" : "async"; }

namespace {

struct QueryBoxGpu {
  glm::vec4 min, max;  // camera-relative
};
constexpr GLuint kQueryViewBinding = 3;

}  // namespace

OcclusionCuller::~OcclusionCuller() = default;
OcclusionCuller::OcclusionCuller(OcclusionCuller&&) noexcept = default;
OcclusionCuller& OcclusionCuller::operator=(OcclusionCuller&&) noexcept = default;

OcclusionCuller::OcclusionCuller()
    : program_(gl::loadProgram({"query_box.vert", "query_box.frag"})),
      viewUniforms_(kQueryViewBinding, sizeof(glm::mat4)),
      scratch_(std::make_unique<Scratch>()) {
  const float corners[8][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}, {1, 1, 1}};
  // 12 triangles, counter-clockwise seen from outside. A query draws the front faces only: a
  // queried box lies wholly beyond the near plane (visibleWithoutQuery), so its front faces cover
  // its silhouette, and at every pixel the front face is nearer than the back face, so a back face
  // passes the depth test only where the front face does. The result is zero exactly when both
  // sides' would be, for half the fragments.
  const unsigned indices[36] = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
                                2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
  cube_ = gl::Buffer(sizeof(corners), corners, 0);
  cubeIndices_ = gl::Buffer(sizeof(indices), indices, 0);
  const GLuint vao = vertexArray_.id();
  glVertexArrayVertexBuffer(vao, 0, cube_.id(), 0, 3 * sizeof(float));
  glVertexArrayElementBuffer(vao, cubeIndices_.id());
  glEnableVertexArrayAttrib(vao, 0);
  glVertexArrayAttribFormat(vao, 0, 3, GL_FLOAT, GL_FALSE, 0);
  glVertexArrayAttribBinding(vao, 0, 0);
  boxes_ = std::make_unique<gl::StreamRing>(4096 * sizeof(QueryBoxGpu), sizeof(QueryBoxGpu));
  glVertexArrayVertexBuffer(vao, 1, boxes_->id(), 0, sizeof(QueryBoxGpu));
  glVertexArrayBindingDivisor(vao, 1, 1);
  for (GLuint a = 1; a <= 2; ++a) {
    glEnableVertexArrayAttrib(vao, a);
    glVertexArrayAttribFormat(vao, a, 4, GL_FLOAT, GL_FALSE, (a - 1) * sizeof(glm::vec4));
    glVertexArrayAttribBinding(vao, a, 1);
  }
}

void OcclusionCuller::reset() {
  state_.clear();
  stateOf_ = nullptr;
}

void OcclusionCuller::beginQueries() {
  if (queryState_) return;
  queryState_ = true;
  ++switches_;
  glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
  glDepthMask(GL_FALSE);
  glEnable(GL_CULL_FACE);  // the front faces (the cube's winding): see the constructor
  glCullFace(GL_BACK);
  glFrontFace(GL_CCW);
  viewUniforms_.bind(viewBlock_);
  program_.use();
  glBindVertexArray(vertexArray_.id());
}

void OcclusionCuller::endQueries() {
  if (!queryState_) return;
  queryState_ = false;
  ++switches_;
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glDepthMask(GL_TRUE);
  glEnable(GL_CULL_FACE);
  glBindVertexArray(0);
}

std::size_t OcclusionCuller::issueQuery(std::span<const Aabb> boxes) {
  if (used_ == pool_.size()) pool_.emplace_back(GL_SAMPLES_PASSED);
  const std::size_t slot = used_++;
  const GLuint ringBefore = boxes_->id();
  const gl::StreamRing::Allocation part = boxes_->allocate(boxes.size() * sizeof(QueryBoxGpu));
  if (boxes_->id() != ringBefore) glVertexArrayVertexBuffer(vertexArray_.id(), 1, boxes_->id(), 0, sizeof(QueryBoxGpu));
  auto* out = static_cast<QueryBoxGpu*>(part.data);
  for (const Aabb& box : boxes) {
    // Camera-relative in double, grown by 4 float ulps of its largest coordinate so that a face
    // never sits behind the geometry it bounds after rounding.
    const dvec3 lo = box.min - eye_, hi = box.max - eye_;
    const double magnitude = std::max(glm::length(glm::max(glm::abs(lo), glm::abs(hi))), 1.0);
    const double grow = 4.0 * 0x1p-23 * magnitude;
    *out++ = {glm::vec4(glm::vec3(lo - grow), 1.0f), glm::vec4(glm::vec3(hi + grow), 1.0f)};
  }
  beginQueries();
  glBeginQuery(GL_SAMPLES_PASSED, pool_[slot].id());
  glDrawElementsInstancedBaseInstance(GL_TRIANGLES, 36, GL_UNSIGNED_INT, nullptr, static_cast<GLsizei>(boxes.size()),
                                      static_cast<GLuint>(part.offset / sizeof(QueryBoxGpu)));
  glEndQuery(GL_SAMPLES_PASSED);
  return slot;
}

bool OcclusionCuller::resultAvailable(std::size_t slot, CullingStats& stats) const {
  GLuint available = GL_FALSE;
  glGetQueryObjectuiv(pool_[slot].id(), GL_QUERY_RESULT_AVAILABLE, &available);
  ++stats.availabilityPolls;
  return available != GL_FALSE;
}

std::uint32_t OcclusionCuller::waitResult(std::size_t slot, CullingStats& stats) const {
  const auto start = std::chrono::steady_clock::now();
  // Nothing else to do until it is available: give the core to the driver's threads meanwhile
  // (llvmpipe rasterises on the CPU).
  if (queryMode_ == QueryMode::Async)
    while (!resultAvailable(slot, stats)) std::this_thread::yield();
  GLuint samples = 0;
  glGetQueryObjectuiv(pool_[slot].id(), GL_QUERY_RESULT, &samples);
  stats.waitMilliseconds += 1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return samples;
}

void OcclusionCuller::drawObjects(Traversal& t, std::span<const std::uint32_t> objects) {
  if (objects.empty()) return;
  endQueries();
  t.stats.trianglesDrawn += t.drawer.draw(objects);
  t.stats.objectsDrawn += static_cast<int>(objects.size());
  ++t.stats.drawCalls;
}

void OcclusionCuller::pullUpVisibility(std::int32_t n) {
  // The node itself always (it may still carry last frame's flag); then its ancestors up to the
  // first one already visible this frame (the ones opened this frame were reset to invisible).
  const std::vector<BvhNode>& nodes = stateOf_->nodes();
  state_[n].visible = true;
  for (n = nodes[n].parent; n >= 0 && !state_[n].visible; n = nodes[n].parent) state_[n].visible = true;
}

const CullingResult& OcclusionCuller::cull(const Bvh& bvh, std::span<const Aabb> objectBoxes, const Camera& camera,
                                           CullingStrategy strategy, ObjectDrawer& drawer, const QueryShapes& shapes) {
  if (!shapes.empty() && shapes.ranges.size() != objectBoxes.size())
    throw Error(fmt::format("OcclusionCuller: query shapes for {} objects, expected {}", shapes.ranges.size(), objectBoxes.size()));
  if (objectBoxes.size() != bvh.objectCount())
    throw Error(fmt::format("OcclusionCuller: {} object boxes for a BVH over {}", objectBoxes.size(), bvh.objectCount()));
  CullingResult& result = result_;
  result.stats = CullingStats{};
  result.visibleObjects.clear();
  Scratch& scratch = *scratch_;
  scratch.clear();
  ++frame_;
  used_ = 0;
  switches_ = 0;
  eye_ = camera.position;
  const glm::dmat4 view = camera.view();
  viewProjectionRelative_ = camera.projection() * view * glm::translate(glm::dmat4(1.0), eye_);
  viewBlock_ = glm::mat4(viewProjectionRelative_);
  if (stateOf_ != &bvh || state_.size() != bvh.nodes().size()) {
    state_.assign(bvh.nodes().size(), NodeState{});
    stateOf_ = &bvh;
    scratch_->reserve(bvh.nodes().size(), bvh.objectCount(), shapes.boxes.size(), result_.visibleObjects);
    pool_.reserve(2 * bvh.nodes().size());
  }
  Traversal t{bvh, camera, view, Frustum(camera), drawer, result.stats, result.visibleObjects, scratch, shapes,
              parameters_.tight_box_area_ratio};
  const std::vector<BvhNode>& nodes = bvh.nodes();

  switch (strategy) {
    case CullingStrategy::None:
    case CullingStrategy::Frustum: {
      std::vector<std::int32_t>& stack = scratch.stack;
      if (!nodes.empty()) stack.push_back(0);
      while (!stack.empty()) {
        const std::int32_t n = stack.back();
        stack.pop_back();
        if (strategy == CullingStrategy::Frustum && !t.frustum.mayIntersect(nodes[n].bounds)) continue;
        ++result.stats.nodesVisited;
        if (nodes[n].leaf()) {
          t.markVisible(n);
        } else {
          stack.push_back(nodes[n].right);
          stack.push_back(nodes[n].left);
        }
      }
      std::sort(t.visible.begin(), t.visible.end());
      drawObjects(t, t.visible);
      break;
    }
    case CullingStrategy::StopAndWait: {
      EntryHeap& traversal = scratch.traversal;
      if (!nodes.empty()) traversal.push(t.entry(0));
      while (!traversal.empty()) {
        const std::int32_t n = traversal.top().node;
        traversal.pop();
        if (!t.frustum.mayIntersect(nodes[n].bounds)) continue;
        ++result.stats.nodesVisited;
        bool isVisible = true;
        if (!t.visibleWithoutQuery(n)) {
          scratch.boxes.clear();
          t.appendQueryBoxes(n, scratch.boxes);
          const std::size_t slot = issueQuery(scratch.boxes);
          ++result.stats.queriesIssued;
          isVisible = waitResult(slot, result.stats) > 0;
        }
        if (!isVisible) continue;
        if (nodes[n].leaf()) {
          drawObjects(t, t.objectsOf(n));
          t.markVisible(n);
        } else {
          traversal.push(t.entry(nodes[n].left));
          traversal.push(t.entry(nodes[n].right));
        }
      }
      break;
    }
    case CullingStrategy::Chc: cullChc(t); break;
    case CullingStrategy::ChcPlusPlus: cullChcPlusPlus(t); break;
  }
  endQueries();
  result.stats.stateSwitches = switches_;

  std::vector<std::uint32_t>& visible = t.visible;
  std::sort(visible.begin(), visible.end());
  visible.erase(std::unique(visible.begin(), visible.end()), visible.end());
  result.farDepth = farDepthOf(visible, objectBoxes, camera);
  return result;
}

// CHC (Bittner et al. 2004, fig. 4).
void OcclusionCuller::cullChc(Traversal& t) {
  const std::vector<BvhNode>& nodes = t.nodes();
  EntryHeap& traversal = t.scratch.traversal;
  // Each pending query holds one node (first); drawnAlready: a previously visible leaf, drawn at
  // once and queried for the next frame.
  FifoQueue<PendingQuery>& queries = t.scratch.pending;
  auto traverseNode = [&](std::int32_t n) {
    if (nodes[n].leaf()) {
      drawObjects(t, t.objectsOf(n));
    } else {
      traversal.push(t.entry(nodes[n].left));
      traversal.push(t.entry(nodes[n].right));
    }
  };
  auto handleResult = [&](const PendingQuery& p, std::uint32_t samples) {
    if (samples == 0) return;
    const std::int32_t node = static_cast<std::int32_t>(p.first);
    pullUpVisibility(node);
    if (nodes[node].leaf()) t.markVisible(node);
    if (!p.drawnAlready) traverseNode(node);
  };
  if (!nodes.empty()) traversal.push(t.entry(0));
  int steps = 0;
  while (!traversal.empty() || !queries.empty()) {
    // Results: all when nothing is left to traverse; else deterministic: at each batch boundary
    // those issued a batch ago; async: whichever the GPU has finished (fig. 4).
    auto ready = [&] {
      if (traversal.empty()) return true;
      if (queryMode_ == QueryMode::Async) return resultAvailable(queries.front().slot, t.stats);
      return steps % kBatchSteps == 0 && queries.front().step <= steps - kBatchSteps;
    };
    while (!queries.empty() && ready()) {
      const PendingQuery p = queries.front();
      queries.pop();
      handleResult(p, waitResult(p.slot, t.stats));
    }
    if (traversal.empty()) continue;
    ++steps;
    const std::int32_t n = traversal.top().node;
    traversal.pop();
    if (!t.frustum.mayIntersect(nodes[n].bounds)) continue;
    ++t.stats.nodesVisited;
    NodeState& s = state_[n];
    if (t.visibleWithoutQuery(n)) {
      s.lastVisited = frame_;
      pullUpVisibility(n);
      if (nodes[n].leaf()) t.markVisible(n);
      traverseNode(n);
      continue;
    }
    const bool wasVisible = s.visible && s.lastVisited + 1 == frame_;
    const bool opened = wasVisible && !nodes[n].leaf();
    s.visible = false;
    s.lastVisited = frame_;
    if (!opened) {
      t.scratch.boxes.clear();
      t.appendQueryBoxes(n, t.scratch.boxes);
      queries.push({static_cast<std::size_t>(n), 1, issueQuery(t.scratch.boxes), wasVisible, steps});
      ++t.stats.queriesIssued;
    }
    if (wasVisible) traverseNode(n);
  }
}

}  // namespace forest::culling
