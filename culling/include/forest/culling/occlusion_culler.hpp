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
//                   pulls visibility up to the root;
//   chc++         — CHC++ (Mattausch, Bittner, Wimmer, EG 2008): previously invisible nodes wait in
//                   an i-queue and are queried in batches (§3.1), visible leaves are drawn from a
//                   render queue flushed only before queries are issued (fewer state switches) and
//                   their queries wait in a v-queue issued while the CPU would otherwise wait
//                   (§3.2); a visible leaf is queried again only every n_av frames, the first time
//                   after a random 1…n_av (§3.3) — beyond the paper, a leaf found visible by a
//                   query that went out before the rest of the frame was drawn is first asked
//                   again the next frame, so one found too early is drawn for one frame more, not
//                   up to n_av; nodes likely to stay invisible share one
//                   multiquery, grouped greedily by p_keep(i) = 0.99 − 0.7·e^(−i) after i invisible
//                   frames — a visible multiquery re-queries its nodes one by one (§3.4); queries
//                   draw the boxes of a node's descendants when they are tighter (§3.5).
//                   Beyond the paper (setShownInLastImage): given which objects had a pixel in
//                   the last image, a drawn leaf without one is asked before it is drawn again
//                   and one with a pixel is not re-queried at all. A leaf found visible whose
//                   confirming query then failed is asked, while hidden, only after the
//                   traversal's last draw (with the c-queue), against the finished depth.
//                   Beyond the paper (geometry queries, CullingSettings::geometry_queries): a leaf
//                   whose box query found it visible is queried once more with its objects' own
//                   triangles before it is drawn, and visible leaves are re-queried so; a leaf
//                   found hidden so is queried with its triangles again while it stays hidden. A
//                   box sees through the gaps between nearer crowns; a tree's own triangles do not.
// Each strategy is a unit of its own in src/ (a TraversalStrategy owning its per-node state, one
// file and one row of kStrategies); they share the query machinery (QueryBatches, src/).
// A query is not a GL query object: its box's fragments that pass the depth test write the frame's
// stamp into the query's slot of a persistently mapped buffer (query_box.frag, early fragment
// tests), so a slot holds the stamp exactly when GL_SAMPLES_PASSED would be nonzero. The boxes of
// queries issued one after the other go out in one instanced draw, and no query begins or ends
// (llvmpipe puts each BeginQuery and EndQuery into every screen tile's bin).
// Query results are read in one of two ways (QueryMode): deterministic — never by polling, at
// points fixed by the traversal alone (CHC: every kBatchSteps steps; CHC++: when its traversal
// queue runs dry), so a run traverses, draws and queries the same way every time (tests,
// llvmpipe, where polling and every read flush the command stream) — or async, as in the
// papers — polling the fence of the query's draw and taking a result as soon as the GPU has it
// while traversal goes on; a result is read only after its fence signalled, so the CPU never
// blocks in a read. Both are exact.
// A query tests the node's box (or, for a leaf, its objects' query shapes; grown by a few ulps)
// against the depth of what has been drawn so far, which only gets nearer as more is drawn: a box found hidden holds nothing visible, so the
// geometry pass equals drawing everything (exactness). Boxes holding the eye (grown by z_n) or
// crossing the near plane count as visible without a query.
#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "forest/core/bounds.hpp"
#include "forest/core/camera.hpp"
#include "forest/core/enum_names.hpp"
#include "forest/core/scene.hpp"
#include "forest/culling/bvh.hpp"

namespace forest::culling {

enum class CullingStrategy { None, Frustum, StopAndWait, Chc, ChcPlusPlus };
inline constexpr EnumNames<CullingStrategy, 5> kCullingStrategyNames{
    "culling strategy", {{{CullingStrategy::None, "none"}, {CullingStrategy::Frustum, "frustum"},
                          {CullingStrategy::StopAndWait, "stop-and-wait"}, {CullingStrategy::Chc, "chc"},
                          {CullingStrategy::ChcPlusPlus, "chc++"}}}};
// Whether the strategy asks each leaf it found visible in a frame again once everything it drew
// is drawn (chc++'s c-queue): then parts drawn after the traversal (QueriesAfterTraversal) leave
// only the objects behind those parts in its visible set, and OcclusionCuller::refineVisibleSet
// is not worth its wait.
bool confirmsFoundLeaves(CullingStrategy strategy);

// What a geometry query draws: a shape that holds the object's triangles where the object has one
// (a tree's query hull), or exactly the triangles draw() draws. A leaf whose box meets the near
// plane is asked with its exact triangles: clipped there, a hull's front faces leave holes that
// its culled back faces do not fill, while the object's own triangles are clipped as its draw is.
enum class QueryGeometry { HullOrOwn, Exact };

// What the renderer implements: draw these objects (indices into the BVH's object boxes) into the
// bound framebuffer with the pass's state; return the triangles drawn.
class ObjectDrawer {
 public:
  virtual ~ObjectDrawer() = default;
  virtual long long draw(std::span<const std::uint32_t> objects) = 0;
  // Geometry queries (optional; chc++ with CullingSettings::geometry_queries): whether `object`
  // can be queried with its own triangles (HullOrOwn), and whether its exact triangles are worth
  // asking where its box meets the near plane (Exact; else it counts as visible without a query).
  virtual bool queriesOwnGeometry(std::uint32_t /*object*/, QueryGeometry /*geometry*/) const { return false; }
  // Draws objects[i]'s triangles, exactly as draw() would place them (or, with HullOrOwn, a hull
  // holding them), with a fragment program that writes the culler's frame stamp into result slot
  // slots[i] (query_stamp.frag: the results buffer and the stamp's block are bound by the culler,
  // as are the depth function and masks). Returns the triangles drawn.
  virtual long long drawGeometryQueries(std::span<const std::uint32_t> /*objects*/, std::span<const std::uint32_t> /*slots*/,
                                        QueryGeometry /*geometry*/) {
    return 0;
  }
};

// Query shapes tighter than the objects' boxes (optional): object o is queried with the boxes
// boxes[ranges[o].first, ranges[o].first + ranges[o].count), whose union holds all of its geometry
// (a tree's height slabs, a terrain tile's blocks), instead of its box.
struct QueryShapes {
  struct Range {
    std::uint32_t first = 0, count = 0;
  };
  std::span<const Range> ranges;  // one per object
  std::span<const Aabb> boxes;
  bool empty() const { return ranges.empty(); }
};

class OcclusionCuller;
class QueryBatches;       // src/query_batches.hpp
class TraversalStrategy;  // src/traversal.hpp, one file per strategy
struct TraversalScratch;
class PartQueries;

// Queries of parts of the objects a cull draws (render::TerrainBlockVisibility: the blocks of the
// terrain tiles it draws), asked against the depth of everything the traversal drew. Handed to
// cull(), they are issued after the traversal's last draw and go out with its last batch of
// queries (chc++: the v-queue's last queries and the c-queue), so their results come with that
// batch's and the frame waits for the GPU no more often than without them.
// chc++ also asks the parts held back by its draws during the traversal (issueDuring), with the
// batch of queries that follows each draw, and has the ones found visible drawn as soon as that
// batch's results are in (takeDuring), before its next queries: a part of a drawn object that
// comes into view (the ground in front of the walker, hidden the frame before behind a tree
// beside the path) then hides what is behind it from the rest of the frame's queries, instead of
// being drawn after all of them.
class QueriesAfterTraversal {
 public:
  virtual ~QueriesAfterTraversal() = default;
  // Called once in every cull, after its last draw and before it waits for its last results:
  // issues the queries with culler.issueAfterCull. Their results: culler.afterCullResults().
  virtual void issue(OcclusionCuller& culler) = 0;
  // The most queries issueDuring() and issue() together make in a frame: the culler keeps that
  // many result slots free.
  virtual std::size_t maxQueries() const = 0;
  // chc++: called after each draw that comes before a batch of queries, while no earlier
  // issueDuring's results are untaken: issues queries (culler.issueAfterCull) for what the draws
  // since the last call held back. Returns whether it issued any (then takeDuring follows).
  virtual bool issueDuring(OcclusionCuller& /*culler*/) { return false; }
  // Once those results are readable (the culler waited for the batch they went out with), before
  // the culler draws or queries again: takes them (culler.afterCullResults()) and draws what they
  // found visible. Returns the triangles drawn.
  virtual long long takeDuring(OcclusionCuller& /*culler*/) { return 0; }
};

enum class QueryMode { Deterministic, Async };
inline constexpr EnumNames<QueryMode, 2> kQueryModeNames{
    "query mode", {{{QueryMode::Deterministic, "deterministic"}, {QueryMode::Async, "async"}}}};

struct CullingStats {
  int nodesVisited = 0;      // nodes taken from the traversal queue inside the frustum
  int queriesIssued = 0;     // all queries, multiqueries included
  int multiQueries = 0;      // queries covering several nodes (chc++)
  int geometryQueries = 0;   // queries drawn with the objects' own triangles (chc++)
  int lateQueries = 0;       // chc++: leaves asked after the traversal's last draw (unconfirmed before)
  long long queryTriangles = 0;  // triangles those queries drew (the boxes' are not counted)
  int stateSwitches = 0;     // changes between drawing and querying (colour/depth writes, program)
  int drawCalls = 0;         // ObjectDrawer::draw calls
  int objectsDrawn = 0;
  long long trianglesDrawn = 0;
  double waitMilliseconds = 0.0;  // CPU time blocked on query results (async: polling until available)
  int waits = 0;                  // times the CPU waited for the GPU's query results
  // The cull call's own CPU time, less the waits: traversal, queues and GL submission (on a
  // software renderer the submitting thread's share of the draws' vertex work too).
  double cpuMilliseconds = 0.0;
  int availabilityPolls = 0;      // async: fences polled
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
  ~OcclusionCuller();
  OcclusionCuller(OcclusionCuller&&) noexcept;
  OcclusionCuller& operator=(OcclusionCuller&&) noexcept;

  // One frame. `objectBoxes[i]` is object i's box (the BVH was built over them). The framebuffer
  // the pass draws into must be bound and cleared; depth test GL_GREATER (reversed-Z). Objects are
  // drawn with back faces culled (GL_BACK, counter-clockwise front faces), the state the queries
  // leave, since they draw the boxes' front faces only. The result is the culler's, valid until
  // its next frame (its storage is reused: no allocation per frame).
  // `shapes`: what a leaf's query draws instead of the leaf's box (none: the box).
  // `after`: queries issued after the traversal's last draw, answered with its last batch.
  const CullingResult& cull(const Bvh& bvh, std::span<const Aabb> objectBoxes, const Camera& camera, CullingStrategy strategy,
                            ObjectDrawer& drawer, const QueryShapes& shapes = {}, QueriesAfterTraversal* after = nullptr);
  // After cull(), in the same frame, framebuffer and state: one query per group of boxes against
  // the depth drawn so far (group g holds boxes [groupEnds[g − 1], groupEnds[g]), from 0 for the
  // first), all in one batch, then the results (deterministic: one wait; async: each fence
  // polled). visible[g]: a sample of group g passed, or a box of it holds the eye or meets the
  // near slab (visible without a query, as in the traversal). With `surfaces`, a group is drawn
  // by surfaces(groups, slots) — group groups[i]'s own triangles, writing the culler's stamp into
  // slot slots[i] (query_stamp.frag), with GL_GEQUAL so that one drawn already passes where it is
  // nearest — instead of its boxes; the boxes then only decide the visible-without-a-query rule.
  // With `bySurface` too (one flag per group), only the flagged groups are drawn so; the others
  // by their boxes.
  // Counted in the frame's result's stats (queries, geometry queries and their triangles, waits,
  // CPU time). For parts of objects the traversal drew in part
  // (render::TerrainBlockVisibility); valid until the next call.
  using SurfaceQueries = std::function<long long(std::span<const std::uint32_t> groups, std::span<const std::uint32_t> slots)>;
  const std::vector<bool>& queryAfterCull(std::span<const Aabb> boxes, std::span<const std::uint32_t> groupEnds,
                                          const SurfaceQueries& surfaces = {});
  // queryAfterCull in two halves: issue the queries (from QueriesAfterTraversal::issue, inside the
  // cull, or after it), then take their results (waiting only for what the cull's last wait did
  // not cover). Inside a cull at most `after->maxQueries()` (or reserveAfterCull's count).
  void issueAfterCull(std::span<const Aabb> boxes, std::span<const std::uint32_t> groupEnds, const SurfaceQueries& surfaces = {},
                      std::span<const std::uint8_t> bySurface = {});
  const std::vector<bool>& afterCullResults();
  // After cull() and every other draw of the frame: asks each object of the frame's visible set
  // again, by its query shapes (or its box), against the final depth, in one batch
  // (queryAfterCull), and keeps those that pass or are visible without a query; z_f again from
  // them. The final depth holds the object itself, but behind its boxes' front faces, so an
  // object with a visible pixel passes: the set stays a superset of what shows. Objects the
  // traversal found visible against a depth that lacked later occluders (terrain blocks drawn
  // after it: render::TerrainBlockVisibility) drop out. Returns the frame's result.
  const CullingResult& refineVisibleSet(std::span<const Aabb> objectBoxes, const QueryShapes& shapes = {});
  // Room for `queries` queries after each cull (queryAfterCull, refineVisibleSet: the visible
  // set's objects and their boxes count) and `boxes` boxes, so that a steady frame allocates
  // nothing; more grows the buffers when asked.
  void reserveAfterCull(std::size_t queries, std::size_t boxes);
  // Which objects had a pixel in the image of the frame drawn with the previous cull (one flag
  // per object, the geometry pass's object IDs: render::ImageVisibility), for the next cull only;
  // an empty span (the default) when not known. Beyond the paper (chc++): a leaf drawn then
  // without a pixel is not drawn untested again — it is asked first, as a hidden leaf; a leaf
  // with a pixel is drawn and needs no re-query (§3.3's n_av interval stands in for exactly this
  // knowledge). Exact whatever the flags say: they only decide between drawing untested and asking.
  // After frames drawn without queries (none, frustum: culling::QueryPayoff's fallback), chc++'s
  // frame-to-frame state is stale; the first chc++ cull after them takes it from these flags
  // instead: a leaf with a shown object was visible, every other node hidden (as if chc++ had
  // drawn that frame). Without flags it starts as from scratch, every node asked again.
  void setShownInLastImage(std::span<const std::uint8_t> shown) { shownInLastImage_ = shown; }
  // Forgets the previous frame's visibility (after a BVH rebuild or a camera cut).
  void reset();
  // The chc++ parameters (the scene file's [culling] section); takes effect next frame.
  void setParameters(const CullingSettings& parameters) { parameters_ = parameters; }
  // How results are read (default deterministic); takes effect next frame.
  void setQueryMode(QueryMode mode) { queryMode_ = mode; }
  QueryMode queryMode() const { return queryMode_; }

 private:
  // The cull's start: the frame's number and query batches, cleared lists and counters, and room
  // for the BVH's nodes, objects and queries.
  void beginCull(const Bvh& bvh, const Camera& camera, const QueryShapes& shapes, ObjectDrawer& drawer, QueriesAfterTraversal* after);
  TraversalStrategy& strategyUnit(CullingStrategy strategy);

  std::unique_ptr<QueryBatches> queries_;  // slots, batches, fences, results
  std::array<std::unique_ptr<TraversalStrategy>, 5> strategies_;  // one per CullingStrategy, made on first use
  std::unique_ptr<TraversalScratch> scratch_;  // the traversals' lists, kept so a steady frame allocates nothing
  std::unique_ptr<PartQueries> parts_;         // the cull's QueriesAfterTraversal
  CullingSettings parameters_;
  QueryMode queryMode_ = QueryMode::Deterministic;
  std::span<const std::uint8_t> shownInLastImage_;  // setShownInLastImage's, for one cull
  const Bvh* culledBvh_ = nullptr;  // the BVH the lists, slots and node states are sized for
  std::size_t culledNodes_ = 0;     // and its node count
  std::uint64_t frame_ = 0;
  Camera camera_;  // the last cull's
  CullingResult result_;
  // queryAfterCull's slots, groups and results; refineVisibleSet's boxes.
  std::vector<std::size_t> afterCullSlots_;
  std::vector<std::uint32_t> afterCullGroups_, afterCullGroupSlots_;  // its surface queries
  std::vector<bool> afterCullVisible_;
  std::vector<Aabb> refineBoxes_;
  std::vector<std::uint32_t> refineEnds_;
  std::size_t afterCullQueries_ = 0;  // reserveAfterCull's
  bool afterCullIssued_ = false;      // issueAfterCull was called, afterCullResults not yet
  bool inCull_ = false;
};

}  // namespace forest::culling
