#include "forest/culling/occlusion_culler.hpp"

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <queue>

#include "forest/core/error.hpp"
#include "forest/core/frustum.hpp"

namespace forest::culling {
namespace {

using glm::dvec3;

// Query results are collected at batch boundaries, every kBatchSteps traversal steps: the queries
// issued before the previous boundary are taken (waiting if need be), the newer ones stay pending
// while traversal and drawing go on. Taking results at fixed points, not whenever the driver
// happens to have them, makes the traversal — and so the visible set, z_f and the shadows —
// identical from run to run; polling for availability would also flush llvmpipe's command stream.
constexpr int kBatchSteps = 64;

// Eye-space depth range of a box's corners.
std::pair<double, double> depthRange(const Aabb& box, const glm::dmat4& view) {
  double nearest = std::numeric_limits<double>::infinity(), farthest = -nearest;
  for (int c = 0; c < 8; ++c) {
    const double depth = -(view * glm::dvec4(box.corner(c), 1.0)).z;
    nearest = std::min(nearest, depth);
    farthest = std::max(farthest, depth);
  }
  return {nearest, farthest};
}

// Visible without a query: the box holds the eye (grown by z_n) or reaches in front of the near
// plane, where its rasterised faces would be clipped away.
bool visibleWithoutQuery(const Aabb& box, const Camera& camera, const glm::dmat4& view) {
  const Aabb grown{box.min - dvec3(camera.near), box.max + dvec3(camera.near)};
  if (grown.contains(camera.position)) return true;
  return depthRange(box, view).first <= camera.near;
}

double distanceToBox(const Aabb& box, const dvec3& p) {
  return glm::length(glm::max(glm::max(box.min - p, p - box.max), dvec3(0.0)));
}

struct Entry {
  double distance;
  std::int32_t node;
  bool operator<(const Entry& other) const { return distance > other.distance; }  // nearest first
};

}  // namespace

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
  throw InputError(fmt::format("culling strategy '{}': expected none, frustum, stop-and-wait or chc", name));
}

std::string_view cullingStrategyName(CullingStrategy strategy) {
  switch (strategy) {
    case CullingStrategy::None: return "none";
    case CullingStrategy::Frustum: return "frustum";
    case CullingStrategy::StopAndWait: return "stop-and-wait";
    case CullingStrategy::Chc: return "chc";
  }
  return "?";
}

OcclusionCuller::OcclusionCuller() : program_(gl::loadProgram({"query_box.vert", "query_box.frag"})) {
  const float corners[8][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}, {1, 1, 1}};
  // 12 triangles; both sides are rasterised (culling is off while querying).
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
}

void OcclusionCuller::reset() {
  state_.clear();
  stateOf_ = nullptr;
}

void OcclusionCuller::beginQueries() {
  if (queryState_) return;
  queryState_ = true;
  glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
  glDepthMask(GL_FALSE);
  glDisable(GL_CULL_FACE);
  program_.use();
  glBindVertexArray(vertexArray_.id());
}

void OcclusionCuller::endQueries() {
  if (!queryState_) return;
  queryState_ = false;
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glDepthMask(GL_TRUE);
  glEnable(GL_CULL_FACE);
  glBindVertexArray(0);
}

std::size_t OcclusionCuller::issueQuery(const Aabb& box) {
  if (used_ == pool_.size()) pool_.emplace_back(GL_SAMPLES_PASSED);
  const std::size_t slot = used_++;
  beginQueries();
  // Camera-relative in double, grown by 4 float ulps of its largest coordinate so that a face never
  // sits behind the geometry it bounds after rounding.
  const dvec3 lo = box.min - eye_, hi = box.max - eye_;
  const double magnitude = std::max(glm::length(glm::max(glm::abs(lo), glm::abs(hi))), 1.0);
  const double grow = 4.0 * 0x1p-23 * magnitude;
  program_.set("uMin", glm::vec3(lo - grow));
  program_.set("uMax", glm::vec3(hi + grow));
  glBeginQuery(GL_SAMPLES_PASSED, pool_[slot].id());
  glDrawElements(GL_TRIANGLES, 36, GL_UNSIGNED_INT, nullptr);
  glEndQuery(GL_SAMPLES_PASSED);
  return slot;
}

std::uint32_t OcclusionCuller::waitResult(std::size_t slot, CullingStats& stats) const {
  const auto start = std::chrono::steady_clock::now();
  GLuint samples = 0;
  glGetQueryObjectuiv(pool_[slot].id(), GL_QUERY_RESULT, &samples);
  stats.waitMilliseconds += 1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return samples;
}

CullingResult OcclusionCuller::cull(const Bvh& bvh, std::span<const Aabb> objectBoxes, const Camera& camera,
                                    CullingStrategy strategy, ObjectDrawer& drawer) {
  if (objectBoxes.size() != bvh.objectCount())
    throw Error(fmt::format("OcclusionCuller: {} object boxes for a BVH over {}", objectBoxes.size(), bvh.objectCount()));
  CullingResult result;
  ++frame_;
  used_ = 0;
  eye_ = camera.position;
  const glm::dmat4 view = camera.view();
  viewProjectionRelative_ = camera.projection() * view * glm::translate(glm::dmat4(1.0), eye_);
  program_.set("uViewProjectionRelative", glm::mat4(viewProjectionRelative_));
  if (stateOf_ != &bvh || state_.size() != bvh.nodes().size()) {
    state_.assign(bvh.nodes().size(), NodeState{});
    stateOf_ = &bvh;
  }
  const std::vector<BvhNode>& nodes = bvh.nodes();
  const Frustum frustum(camera);
  std::vector<std::uint32_t> visible;

  auto drawLeaf = [&](std::int32_t n) {
    const BvhNode& node = nodes[n];
    const std::span<const std::uint32_t> objects(bvh.objects().data() + node.first, node.count);
    endQueries();
    result.stats.trianglesDrawn += drawer.draw(objects);
    result.stats.objectsDrawn += static_cast<int>(node.count);
  };
  auto markVisible = [&](std::int32_t n) {
    const BvhNode& node = nodes[n];
    for (std::uint32_t k = node.first; k < node.first + node.count; ++k) visible.push_back(bvh.objects()[k]);
  };

  if (strategy == CullingStrategy::None || strategy == CullingStrategy::Frustum) {
    std::vector<std::uint32_t> drawn;
    std::vector<std::int32_t> stack;
    if (!nodes.empty()) stack.push_back(0);
    while (!stack.empty()) {
      const std::int32_t n = stack.back();
      stack.pop_back();
      if (strategy == CullingStrategy::Frustum && !frustum.mayIntersect(nodes[n].bounds)) continue;
      ++result.stats.nodesVisited;
      if (nodes[n].leaf()) {
        for (std::uint32_t k = nodes[n].first; k < nodes[n].first + nodes[n].count; ++k) drawn.push_back(bvh.objects()[k]);
      } else {
        stack.push_back(nodes[n].right);
        stack.push_back(nodes[n].left);
      }
    }
    std::sort(drawn.begin(), drawn.end());
    result.stats.trianglesDrawn = drawer.draw(drawn);
    result.stats.objectsDrawn = static_cast<int>(drawn.size());
    visible = std::move(drawn);
  } else if (strategy == CullingStrategy::StopAndWait) {
    std::priority_queue<Entry> traversal;
    if (!nodes.empty()) traversal.push({distanceToBox(nodes[0].bounds, eye_), 0});
    while (!traversal.empty()) {
      const std::int32_t n = traversal.top().node;
      traversal.pop();
      if (!frustum.mayIntersect(nodes[n].bounds)) continue;
      ++result.stats.nodesVisited;
      bool isVisible = true;
      if (!visibleWithoutQuery(nodes[n].bounds, camera, view)) {
        const std::size_t slot = issueQuery(nodes[n].bounds);
        ++result.stats.queriesIssued;
        isVisible = waitResult(slot, result.stats) > 0;
      }
      if (!isVisible) continue;
      if (nodes[n].leaf()) {
        drawLeaf(n);
        markVisible(n);
      } else {
        traversal.push({distanceToBox(nodes[nodes[n].left].bounds, eye_), nodes[n].left});
        traversal.push({distanceToBox(nodes[nodes[n].right].bounds, eye_), nodes[n].right});
      }
    }
  } else {  // CHC (Bittner et al. 2004, fig. 4)
    std::priority_queue<Entry> traversal;
    struct Pending {
      std::int32_t node;
      std::size_t slot;
      bool leafAlreadyDrawn;  // a previously visible leaf: drawn at once, queried for the next frame
      int step;               // traversal step at which it was issued
    };
    std::deque<Pending> queries;
    auto traverseNode = [&](std::int32_t n) {
      if (nodes[n].leaf()) {
        drawLeaf(n);
      } else {
        traversal.push({distanceToBox(nodes[nodes[n].left].bounds, eye_), nodes[n].left});
        traversal.push({distanceToBox(nodes[nodes[n].right].bounds, eye_), nodes[n].right});
      }
    };
    auto pullUpVisibility = [&](std::int32_t n) {
      while (n >= 0 && !state_[n].visible) {
        state_[n].visible = true;
        n = nodes[n].parent;
      }
    };
    auto handleResult = [&](const Pending& p, std::uint32_t samples) {
      if (samples == 0) return;
      pullUpVisibility(p.node);
      if (nodes[p.node].leaf()) markVisible(p.node);
      if (!p.leafAlreadyDrawn) traverseNode(p.node);
    };
    if (!nodes.empty()) traversal.push({distanceToBox(nodes[0].bounds, eye_), 0});
    int steps = 0;
    while (!traversal.empty() || !queries.empty()) {
      // Results: at each batch boundary those issued a batch ago; all when nothing is left to traverse.
      while (!queries.empty() &&
             (traversal.empty() || (steps % kBatchSteps == 0 && queries.front().step <= steps - kBatchSteps))) {
        const Pending p = queries.front();
        queries.pop_front();
        handleResult(p, waitResult(p.slot, result.stats));
      }
      if (traversal.empty()) continue;
      ++steps;
      const std::int32_t n = traversal.top().node;
      traversal.pop();
      if (!frustum.mayIntersect(nodes[n].bounds)) continue;
      ++result.stats.nodesVisited;
      NodeState& s = state_[n];
      if (visibleWithoutQuery(nodes[n].bounds, camera, view)) {
        s.lastVisited = frame_;
        pullUpVisibility(n);
        if (nodes[n].leaf()) markVisible(n);
        traverseNode(n);
        continue;
      }
      const bool wasVisible = s.visible && s.lastVisited + 1 == frame_;
      const bool opened = wasVisible && !nodes[n].leaf();
      s.visible = false;
      s.lastVisited = frame_;
      if (!opened) {
        queries.push_back({n, issueQuery(nodes[n].bounds), wasVisible, steps});
        ++result.stats.queriesIssued;
      }
      if (wasVisible) traverseNode(n);
    }
  }
  endQueries();

  std::sort(visible.begin(), visible.end());
  visible.erase(std::unique(visible.begin(), visible.end()), visible.end());
  result.farDepth = farDepthOf(visible, objectBoxes, camera);
  result.visibleObjects = std::move(visible);
  return result;
}

}  // namespace forest::culling
