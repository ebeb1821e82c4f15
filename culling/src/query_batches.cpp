#include "query_batches.hpp"

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <cstring>
#include <thread>

#include "forest/core/error.hpp"

namespace forest::culling {

using glm::dvec3;

namespace {
constexpr GLuint kQueryViewBinding = 3;     // query_block.glsl
constexpr GLuint kQueryResultsBinding = 2;  // query_box.frag, query_stamp.frag
}  // namespace

QueryBatches::QueryBatches()
    : program_(gl::loadProgram({"query_box.vert", "query_box.frag"}, gl::readShader("query_block.glsl"))),
      viewUniforms_(kQueryViewBinding, sizeof(QueryView)) {
  const float corners[8][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}, {1, 1, 1}};
  // 12 triangles, counter-clockwise seen from outside. A query draws the front faces only: a
  // queried box lies wholly beyond the near plane (visible without a query otherwise), so its
  // front faces cover its silhouette, and at every pixel the front face is nearer than the back
  // face, so a back face passes the depth test only where the front face does. The result is zero
  // exactly when both sides' would be, for half the fragments.
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

void QueryBatches::beginFrame(std::uint64_t frame, const Camera& camera, ObjectDrawer& drawer, QueryMode mode) {
  dropFences();  // left by after-cull queries whose results were not taken
  used_ = drawnSlots_ = readableSlots_ = 0;
  switches_ = 0;
  mode_ = mode;
  eye_ = camera.position;
  const glm::dmat4 viewProjectionRelative = camera.projection() * camera.view() * glm::translate(glm::dmat4(1.0), eye_);
  view_.viewProjectionRelative = glm::mat4(viewProjectionRelative);
  // Nonzero (the cleared slots hold 0); after 2³² frames a stamp repeats, and a slot unwritten
  // since then would read visible: a node drawn or opened needlessly, never a pixel lost.
  view_.frameStamp.x = static_cast<std::uint32_t>(frame % 0xffffffffu) + 1u;
  drawer_ = &drawer;
}

void QueryBatches::endFrame(CullingStats& stats) {
  drawBatch(stats);  // none left unread by the strategies; kept for a query issued last
  endQueryState();
  drawer_ = nullptr;  // geometry queries only within a frame's cull
}

void QueryBatches::reserveSlots(std::size_t slots) {
  if (slots_ >= slots) return;
  results_ = gl::ReadMappedStamps(slots);
  slots_ = slots;
}

void QueryBatches::growAfterFrame(std::size_t slots) {
  results_ = gl::ReadMappedStamps(slots);
  slots_ = slots;
  drawnSlots_ = readableSlots_ = used_;
}

void QueryBatches::reserveBatch(std::size_t boxes, std::size_t objects) {
  batch_.reserve(boxes);
  for (GeometryQueries& queries : geometryQueries_) {
    queries.objects.reserve(objects);
    queries.slots.reserve(objects);
  }
}

void QueryBatches::beginQueryState() {
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

void QueryBatches::endQueryState() {
  if (!queryState_) return;
  queryState_ = false;
  ++switches_;
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glDepthMask(GL_TRUE);
  glEnable(GL_CULL_FACE);
  glBindVertexArray(0);
}

// At most 3N + 1 per frame for a BVH of N nodes (slotsForFrame, with the queries after the cull): a node enters the traversal once, and is queried once for itself, once more
// when a multiquery that held it found something; a leaf also once with its own triangles (its
// geometry query) and, found visible, once more after the frame is drawn (chc++'s c-queue). With
// L leaves and L − 1 inner nodes that is 4L + 2(L − 1) = 3N + 1.
std::size_t QueryBatches::takeSlot() {
  if (used_ == slots_) throw Error(fmt::format("OcclusionCuller: more than {} queries in a frame", slots_));
  return used_++;
}

std::size_t QueryBatches::issueGeometry(std::span<const std::uint32_t> objects, QueryGeometry geometry) {
  const std::size_t slot = takeSlot();
  GeometryQueries& queries = geometryQueries_[static_cast<std::size_t>(geometry)];
  queries.objects.insert(queries.objects.end(), objects.begin(), objects.end());
  queries.slots.insert(queries.slots.end(), objects.size(), static_cast<std::uint32_t>(slot));
  return slot;
}

std::size_t QueryBatches::issueBoxes(std::span<const Aabb> boxes) {
  const std::size_t slot = takeSlot();
  for (const Aabb& box : boxes) {
    // Camera-relative in double, grown by 4 float ulps of its largest coordinate so that a face
    // never sits behind the geometry it bounds after rounding.
    const dvec3 lo = box.min - eye_, hi = box.max - eye_;
    const double magnitude = std::max(glm::length(glm::max(glm::abs(lo), glm::abs(hi))), 1.0);
    const double grow = 4.0 * 0x1p-23 * magnitude;
    batch_.push_back({glm::vec3(lo - grow), static_cast<std::uint32_t>(slot), glm::vec3(hi + grow), 0u});
  }
  return slot;
}

void QueryBatches::drawBatch(CullingStats& stats) {
  if (!batchPending()) return;
  if (!batch_.empty()) {
    beginQueryState();
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
    beginQueryState();
    glDepthFunc(GL_GEQUAL);
    for (const QueryGeometry geometry : {QueryGeometry::HullOrOwn, QueryGeometry::Exact}) {
      GeometryQueries& queries = geometryQueries_[static_cast<std::size_t>(geometry)];
      if (queries.objects.empty()) continue;
      stats.queryTriangles += drawer_->drawGeometryQueries(queries.objects, queries.slots, geometry);
      queries.objects.clear();
      queries.slots.clear();
    }
    glDepthFunc(GL_GREATER);
    endQueryState();
  }
  markDrawn();
}

void QueryBatches::markDrawn() {
  drawnSlots_ = used_;
  if (mode_ == QueryMode::Async) {
    // Shader writes reach a mapped buffer after this barrier and a fence (GL 4.5 §7.12.2); the
    // flush lets the fence signal while the traversal goes on.
    glMemoryBarrier(GL_CLIENT_MAPPED_BUFFER_BARRIER_BIT);
    fences_.push_back({drawnSlots_, glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0)});
    glFlush();
  }
}

void QueryBatches::waitForResults(std::size_t slot, CullingStats& stats) {
  ++stats.waits;
  if (mode_ == QueryMode::Deterministic) {
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

bool QueryBatches::resultAvailable(std::size_t slot, CullingStats& stats) {
  if (slot >= drawnSlots_) drawBatch(stats);
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

bool QueryBatches::waitResult(std::size_t slot, CullingStats& stats) {
  if (slot >= drawnSlots_) drawBatch(stats);
  const auto start = std::chrono::steady_clock::now();
  if (slot >= readableSlots_) waitForResults(slot, stats);
  stats.waitMilliseconds += 1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return results_[slot] == view_.frameStamp.x;
}

void QueryBatches::dropFences() {
  for (const BatchFence& f : fences_) glDeleteSync(f.fence);
  fences_.clear();
}

}  // namespace forest::culling
