#include "forest/culling/occlusion_culler.hpp"

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstring>
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

bool confirmsFoundLeaves(CullingStrategy strategy) { return strategy == CullingStrategy::ChcPlusPlus; }

namespace {
constexpr GLuint kQueryViewBinding = 3;     // query_block.glsl
constexpr GLuint kQueryResultsBinding = 2;  // query_box.frag, query_stamp.frag
}  // namespace

OcclusionCuller::~OcclusionCuller() = default;
OcclusionCuller::OcclusionCuller(OcclusionCuller&&) noexcept = default;
OcclusionCuller& OcclusionCuller::operator=(OcclusionCuller&&) noexcept = default;

OcclusionCuller::OcclusionCuller()
    : program_(gl::loadProgram({"query_box.vert", "query_box.frag"}, gl::readShader("query_block.glsl"))),
      viewUniforms_(kQueryViewBinding, sizeof(QueryView)),
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
  boxes_ = std::make_unique<gl::StreamRing>(4096 * sizeof(QueryBox), sizeof(QueryBox));
  glVertexArrayVertexBuffer(vao, 1, boxes_->id(), 0, sizeof(QueryBox));
  glVertexArrayBindingDivisor(vao, 1, 1);
  for (GLuint a = 1; a <= 3; ++a) {
    glEnableVertexArrayAttrib(vao, a);
    glVertexArrayAttribBinding(vao, a, 1);
  }
  glVertexArrayAttribFormat(vao, 1, 3, GL_FLOAT, GL_FALSE, offsetof(QueryBox, min));
  glVertexArrayAttribFormat(vao, 2, 3, GL_FLOAT, GL_FALSE, offsetof(QueryBox, max));
  glVertexArrayAttribIFormat(vao, 3, 1, GL_UNSIGNED_INT, offsetof(QueryBox, slot));
}

void OcclusionCuller::allocateResultSlots(std::size_t slots) {
  results_ = gl::ReadMappedStamps(slots);
  slots_ = slots;
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
  viewUniforms_.bind(view_);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kQueryResultsBinding, results_.id());
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

std::size_t OcclusionCuller::issueGeometryQuery(std::span<const std::uint32_t> objects, QueryGeometry geometry) {
  const std::uint32_t slot = takeSlot(used_, slots_);
  GeometryQueries& queries = geometryQueries_[static_cast<std::size_t>(geometry)];
  queries.objects.insert(queries.objects.end(), objects.begin(), objects.end());
  queries.slots.insert(queries.slots.end(), objects.size(), slot);
  return slot;
}

std::size_t OcclusionCuller::issueQuery(std::span<const Aabb> boxes) {
  const std::uint32_t slot = takeSlot(used_, slots_);
  for (const Aabb& box : boxes) {
    // Camera-relative in double, grown by 4 float ulps of its largest coordinate so that a face
    // never sits behind the geometry it bounds after rounding.
    const dvec3 lo = box.min - eye_, hi = box.max - eye_;
    const double magnitude = std::max(glm::length(glm::max(glm::abs(lo), glm::abs(hi))), 1.0);
    const double grow = 4.0 * 0x1p-23 * magnitude;
    batch_.push_back({glm::vec3(lo - grow), slot, glm::vec3(hi + grow), 0u});
  }
  return slot;
}

void OcclusionCuller::drawQueryBatch() {
  if (batch_.empty() && !geometryQueriesPending()) return;
  if (!batch_.empty()) {
    beginQueries();
    const GLuint ringBefore = boxes_->id();
    const gl::StreamRing::Allocation part = boxes_->allocate(batch_.size() * sizeof(QueryBox));
    if (boxes_->id() != ringBefore) glVertexArrayVertexBuffer(vertexArray_.id(), 1, boxes_->id(), 0, sizeof(QueryBox));
    std::memcpy(part.data, batch_.data(), batch_.size() * sizeof(QueryBox));
    glDrawElementsInstancedBaseInstance(GL_TRIANGLES, 36, GL_UNSIGNED_INT, nullptr, static_cast<GLsizei>(batch_.size()),
                                        static_cast<GLuint>(part.offset / sizeof(QueryBox)));
    batch_.clear();
  }
  if (geometryQueriesPending()) {
    // The objects' own triangles, as their draw places them; GL_GEQUAL, so that a leaf drawn
    // already this frame (a visible leaf's re-query) passes where its own depth is still the
    // nearest. The drawer binds its own program: the box program is bound again next time.
    beginQueries();
    glDepthFunc(GL_GEQUAL);
    for (const QueryGeometry geometry : {QueryGeometry::HullOrOwn, QueryGeometry::Exact}) {
      GeometryQueries& queries = geometryQueries_[static_cast<std::size_t>(geometry)];
      if (queries.objects.empty()) continue;
      stats_->queryTriangles += drawer_->drawGeometryQueries(queries.objects, queries.slots, geometry);
      queries.objects.clear();
      queries.slots.clear();
    }
    glDepthFunc(GL_GREATER);
    endQueries();
  }
  markQueriesDrawn();
}

void OcclusionCuller::markQueriesDrawn() {
  drawnSlots_ = used_;
  if (queryMode_ == QueryMode::Async) {
    // Shader writes reach a mapped buffer after this barrier and a fence (GL 4.5 §7.12.2); the
    // flush lets the fence signal while the traversal goes on.
    glMemoryBarrier(GL_CLIENT_MAPPED_BUFFER_BARRIER_BIT);
    fences_.push_back({drawnSlots_, glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0)});
    glFlush();
  }
}

void OcclusionCuller::waitForResults(std::size_t slot, CullingStats& stats) {
  ++stats.waits;
  if (queryMode_ == QueryMode::Deterministic) {
    // One barrier and wait for everything drawn so far: the next reads need none (llvmpipe's
    // barrier is a glFinish already).
    glMemoryBarrier(GL_CLIENT_MAPPED_BUFFER_BARRIER_BIT);
    const GLsync fence = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
    while (glClientWaitSync(fence, GL_SYNC_FLUSH_COMMANDS_BIT, 1'000'000'000) == GL_TIMEOUT_EXPIRED) {
    }
    glDeleteSync(fence);
    readableSlots_ = drawnSlots_;
    return;
  }
  // Async: nothing else to do until the fence signals; poll it and give the core to the driver's
  // threads meanwhile (llvmpipe rasterises on the CPU), so no call blocks.
  while (!resultAvailable(slot, stats)) std::this_thread::yield();
}

bool OcclusionCuller::resultAvailable(std::size_t slot, CullingStats& stats) {
  if (slot >= drawnSlots_) drawQueryBatch();
  ++stats.availabilityPolls;
  while (slot >= readableSlots_) {
    const BatchFence next = fences_.front();
    const GLenum status = glClientWaitSync(next.fence, 0, 0);
    if (status == GL_TIMEOUT_EXPIRED) return false;
    glDeleteSync(next.fence);
    fences_.erase(fences_.begin());
    readableSlots_ = next.endSlot;
  }
  return true;
}

bool OcclusionCuller::waitResult(std::size_t slot, CullingStats& stats) {
  if (slot >= drawnSlots_) drawQueryBatch();
  const auto start = std::chrono::steady_clock::now();
  if (slot >= readableSlots_) waitForResults(slot, stats);
  stats.waitMilliseconds += 1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return results_[slot] == view_.frameStamp.x;
}

void OcclusionCuller::drawObjects(Traversal& t, std::span<const std::uint32_t> objects) {
  if (objects.empty()) return;
  drawQueryBatch();  // the queries issued before these objects test the depth without them
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

// A cull's start: the frame's stamp and view, cleared lists and counters, the node state and the
// result slots sized for the BVH.
void OcclusionCuller::beginCull(const Bvh& bvh, const Camera& camera, const QueryShapes& shapes, ObjectDrawer& drawer,
                                QueriesAfterTraversal* after) {
  result_.stats = CullingStats{};
  result_.visibleObjects.clear();
  Scratch& scratch = *scratch_;
  scratch.clear();
  ++frame_;
  for (const BatchFence& f : fences_) glDeleteSync(f.fence);  // left by after-cull queries whose results were not taken
  fences_.clear();
  afterCullIssued_ = duringIssued_ = false;
  used_ = drawnSlots_ = readableSlots_ = 0;
  switches_ = 0;
  eye_ = camera.position;
  camera_ = camera;
  const glm::dmat4 view = camera.view();
  viewProjectionRelative_ = camera.projection() * view * glm::translate(glm::dmat4(1.0), eye_);
  view_.viewProjectionRelative = glm::mat4(viewProjectionRelative_);
  // Nonzero (the cleared slots hold 0); after 2³² frames a stamp repeats, and a slot unwritten
  // since then would read visible: a node drawn or opened needlessly, never a pixel lost.
  view_.frameStamp.x = static_cast<std::uint32_t>(frame_ % 0xffffffffu) + 1u;
  if (stateOf_ != &bvh || state_.size() != bvh.nodes().size()) {
    state_.assign(bvh.nodes().size(), NodeState{});
    stateOf_ = &bvh;
    scratch_->reserve(bvh.nodes().size(), bvh.objectCount(), shapes.boxes.size(), result_.visibleObjects);
    allocateResultSlots(3 * bvh.nodes().size() + 2 + afterCullQueries_);
    for (GeometryQueries& queries : geometryQueries_) {
      queries.objects.reserve(bvh.objectCount());
      queries.slots.reserve(bvh.objectCount());
    }
  }
  if (after && after->maxQueries() > afterCullQueries_) reserveAfterCull(after->maxQueries(), 0);
  drawer_ = &drawer;
  stats_ = &result_.stats;
  afterTraversal_ = after;
  inCull_ = true;
}

// none (every node) or frustum culling: the leaves inside, drawn in one call.
void OcclusionCuller::cullByFrustum(Traversal& t, bool frustum) {
  const std::vector<BvhNode>& nodes = t.nodes();
  std::vector<std::int32_t>& stack = t.scratch.stack;
  if (!nodes.empty()) stack.push_back(0);
  while (!stack.empty()) {
    const std::int32_t n = stack.back();
    stack.pop_back();
    if (frustum && !t.frustum.mayIntersect(nodes[n].bounds)) continue;
    ++t.stats.nodesVisited;
    if (nodes[n].leaf()) {
      t.markVisible(n);
    } else {
      stack.push_back(nodes[n].right);
      stack.push_back(nodes[n].left);
    }
  }
  std::sort(t.visible.begin(), t.visible.end());
  drawObjects(t, t.visible);
}

// stop-and-wait: front to back, each node in the frustum queried and its result waited for.
void OcclusionCuller::cullStopAndWait(Traversal& t) {
  const std::vector<BvhNode>& nodes = t.nodes();
  EntryHeap& traversal = t.scratch.traversal;
  if (!nodes.empty()) traversal.push(t.entry(0));
  while (!traversal.empty()) {
    const std::int32_t n = traversal.top().node;
    traversal.pop();
    if (!t.frustum.mayIntersect(nodes[n].bounds)) continue;
    ++t.stats.nodesVisited;
    bool isVisible = true;
    if (!t.visibleWithoutQuery(n)) {
      t.scratch.boxes.clear();
      t.appendQueryBoxes(n, t.scratch.boxes);
      const std::size_t slot = issueQuery(t.scratch.boxes);
      ++t.stats.queriesIssued;
      isVisible = waitResult(slot, t.stats);
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
}

const CullingResult& OcclusionCuller::cull(const Bvh& bvh, std::span<const Aabb> objectBoxes, const Camera& camera,
                                           CullingStrategy strategy, ObjectDrawer& drawer, const QueryShapes& shapes,
                                           QueriesAfterTraversal* after) {
  if (!shapes.empty() && shapes.ranges.size() != objectBoxes.size())
    throw Error(fmt::format("OcclusionCuller: query shapes for {} objects, expected {}", shapes.ranges.size(), objectBoxes.size()));
  if (objectBoxes.size() != bvh.objectCount())
    throw Error(fmt::format("OcclusionCuller: {} object boxes for a BVH over {}", objectBoxes.size(), bvh.objectCount()));
  const auto start = std::chrono::steady_clock::now();
  CullingResult& result = result_;
  beginCull(bvh, camera, shapes, drawer, after);
  Traversal t{bvh, camera, Frustum(camera), drawer, result.stats, result.visibleObjects, *scratch_, shapes,
              parameters_.tight_box_area_ratio, NearSlab(camera)};
  switch (strategy) {
    case CullingStrategy::None:
    case CullingStrategy::Frustum: cullByFrustum(t, strategy == CullingStrategy::Frustum); break;
    case CullingStrategy::StopAndWait: cullStopAndWait(t); break;
    case CullingStrategy::Chc: cullChc(t); break;
    case CullingStrategy::ChcPlusPlus:
      if (lastStrategy_ == CullingStrategy::None || lastStrategy_ == CullingStrategy::Frustum) takeStateFromLastImage(t);
      cullChcPlusPlus(t);
      break;
  }
  lastStrategy_ = strategy;
  issueAfterTraversal();  // chc++ did before its last wait
  drawQueryBatch();  // none left unread by the strategies; kept for a query issued last
  endQueries();
  drawer_ = nullptr;  // geometry queries only within a cull
  shownInLastImage_ = {};  // setShownInLastImage's flags are for one cull
  stats_ = nullptr;
  inCull_ = false;
  if (!afterCullIssued_) {  // else afterCullResults may still need the fences
    for (const BatchFence& f : fences_) glDeleteSync(f.fence);
    fences_.clear();
  }
  result.stats.stateSwitches = switches_;

  std::vector<std::uint32_t>& visible = t.visible;
  std::sort(visible.begin(), visible.end());
  visible.erase(std::unique(visible.begin(), visible.end()), visible.end());
  result.farDepth = farDepthOf(visible, objectBoxes, camera);
  result.stats.cpuMilliseconds =
      1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() - result.stats.waitMilliseconds;
  return result;
}

void OcclusionCuller::takeStateFromLastImage(Traversal& t) {
  if (shownInLastImage_.empty()) return;
  const std::vector<BvhNode>& nodes = t.nodes();
  const std::uint64_t before = frame_ - 1;
  const std::uint64_t requery = static_cast<std::uint64_t>(std::max(1, parameters_.visible_requery_frames));
  for (NodeState& s : state_) {  // hidden in that frame, as far as the image tells
    s.visible = false;
    s.lastVisited = before;
    s.invisibleFrames = std::min(s.invisibleFrames + 1, 1000);
    s.newlyVisible = s.unconfirmed = false;
  }
  for (std::size_t n = 0; n < nodes.size(); ++n) {
    if (!nodes[n].leaf()) continue;
    bool shown = false;
    for (std::uint32_t o : t.objectsOf(static_cast<std::int32_t>(n)))
      shown = shown || (o < shownInLastImage_.size() && shownInLastImage_[o] != 0);
    if (!shown) continue;
    NodeState& s = state_[n];
    s.invisibleFrames = 0;
    s.geometryHidden = false;
    s.nextQueryFrame = frame_ + requery;
    pullUpVisibility(static_cast<std::int32_t>(n));
  }
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
  auto handleResult = [&](const PendingQuery& p, bool visible) {
    if (!visible) return;
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
