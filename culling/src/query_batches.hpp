#pragma once
// The query machinery every culling strategy shares (internal; DESIGN §4 culling/): result slots,
// batches, fences and the reads of results. A query is not a GL query object: its box's fragments
// that pass the depth test write the frame's stamp into the query's slot of a persistently mapped
// buffer (query_box.frag, early fragment tests), so a slot holds the stamp exactly when
// GL_SAMPLES_PASSED would be nonzero. The boxes of the queries issued one after the other go out
// in one instanced draw (a batch); a geometry query goes out with the batch, drawn by the
// ObjectDrawer with its own triangles (query_stamp.frag).
#include <glm/glm.hpp>

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "forest/core/bounds.hpp"
#include "forest/core/camera.hpp"
#include "forest/culling/occlusion_culler.hpp"
#include "forest/gl/objects.hpp"
#include "forest/gl/shader.hpp"
#include "forest/gl/stream_ring.hpp"
#include "forest/gl/uniform_stream.hpp"

namespace forest::culling {

class QueryBatches {
 public:
  QueryBatches();  // needs a current GL context

  // A frame's start: its stamp (frame number) and camera-relative view, every slot free, no fence
  // left; `drawer` draws the frame's geometry queries, `mode` says how results are read.
  void beginFrame(std::uint64_t frame, const Camera& camera, ObjectDrawer& drawer, QueryMode mode);
  // The frame's last batch is drawn and the query state left; the geometry queries' drawer is
  // forgotten.
  void endFrame(CullingStats& stats);
  // The most slots one frame over a BVH of `nodes` nodes takes (takeSlot), with `afterCull`
  // queries after the cull.
  static std::size_t slotsForFrame(std::size_t nodes, std::size_t afterCull) { return 3 * nodes + 2 + afterCull; }
  // Room for `slots` queries a frame: a larger, zeroed buffer when there is less (results not
  // yet read are lost: only between frames).
  void reserveSlots(std::size_t slots);
  // After a frame whose results were all read or dropped: at least `slots` slots, the ones in use
  // kept unused in a new buffer (queries after the cull that would not fit).
  void growAfterFrame(std::size_t slots);
  // Room for `boxes` boxes and `objects` geometry-query objects in one batch: no growth per frame.
  void reserveBatch(std::size_t boxes, std::size_t objects);

  // Issues one query for the boxes (drawn with the next batch); returns its result slot.
  std::size_t issueBoxes(std::span<const Aabb> boxes);
  // Issues one query drawn with the objects' own triangles (ObjectDrawer::drawGeometryQueries),
  // with the next batch; returns its result slot.
  std::size_t issueGeometry(std::span<const std::uint32_t> objects, QueryGeometry geometry);
  // A slot for a query the caller draws itself in the query state (queryAfterCull's surfaces).
  std::size_t takeSlot();
  // Draws the boxes of the queries issued since the last batch, in one instanced call, and the
  // geometry queries' objects (their triangles counted in stats); async: fences them.
  void drawBatch(CullingStats& stats);
  // The queries issued so far are drawn: their slots may be waited for (async: behind a fence).
  void markDrawn();
  // The query's result (true: a sample passed); waits for it when needed (its batch drawn first).
  bool waitResult(std::size_t slot, CullingStats& stats);
  // Async: whether the query's result is available now (one poll of its fence). Deterministic:
  // never asked.
  bool resultAvailable(std::size_t slot, CullingStats& stats);
  // Deletes the fences of batches not known complete (results no longer wanted).
  void dropFences();

  // The query state (colour and depth writes off, the box program, the results bound) and back;
  // each change counts as a state switch.
  void beginQueryState();
  void endQueryState();

  bool batchPending() const { return !batch_.empty() || geometryQueriesPending(); }
  std::size_t used() const { return used_; }          // slots issued this frame
  std::size_t capacity() const { return slots_; }     // slots in the buffer
  std::size_t readable() const { return readableSlots_; }  // slots whose results the CPU may read
  int stateSwitches() const { return switches_; }
  QueryMode mode() const { return mode_; }

 private:
  // query_box.vert's block (binding 3): the camera-relative view-projection and the frame's
  // stamp, written once per frame.
  struct QueryView {
    glm::mat4 viewProjectionRelative{1.0f};
    glm::uvec4 frameStamp{0u};
  };
  // A query's box as its instance (query_box.vert): camera-relative corners and the result slot.
  struct QueryBox {
    glm::vec3 min;
    std::uint32_t slot;
    glm::vec3 max;
    std::uint32_t padding;
  };
  struct BatchFence {
    std::size_t endSlot;  // the queries before it were drawn before the fence
    GLsync fence;
  };
  // The geometry queries issued since the last batch was drawn: each object and its query's slot.
  struct GeometryQueries {
    std::vector<std::uint32_t> objects, slots;
  };
  void waitForResults(std::size_t slot, CullingStats& stats);
  bool geometryQueriesPending() const { return !geometryQueries_[0].objects.empty() || !geometryQueries_[1].objects.empty(); }

  gl::Program program_;
  gl::UniformStream viewUniforms_;
  QueryView view_;
  gl::VertexArray vertexArray_;
  gl::Buffer cube_;
  gl::Buffer cubeIndices_;
  // The boxes of a batch, camera-relative, written once into a mapped ring (DESIGN §9).
  std::unique_ptr<gl::StreamRing> boxes_;
  std::vector<QueryBox> batch_;  // the boxes of the queries issued since the last batch was drawn
  std::array<GeometryQueries, 2> geometryQueries_;  // per QueryGeometry
  ObjectDrawer* drawer_ = nullptr;  // the current frame's (geometry queries)
  // Per slot, the stamp of the last frame in which a sample of its query passed (query_box.frag):
  // persistently and coherently mapped for reading.
  gl::ReadMappedStamps results_;
  std::size_t slots_ = 0;          // the buffer's capacity
  std::size_t used_ = 0;           // slots issued this frame
  std::size_t drawnSlots_ = 0;     // slots whose boxes have been drawn
  std::size_t readableSlots_ = 0;  // slots whose results the CPU may read
  std::vector<BatchFence> fences_;  // async: the drawn batches not yet known complete
  glm::dvec3 eye_{0.0};
  bool queryState_ = false;
  int switches_ = 0;
  QueryMode mode_ = QueryMode::Deterministic;
};

}  // namespace forest::culling
