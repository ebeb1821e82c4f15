#pragma once
// One culling frame's shared state, the helpers every traversal strategy uses, and the interface
// each strategy implements (internal).
#include <fmt/format.h>
#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <span>
#include <tuple>
#include <utility>
#include <vector>

#include "forest/core/error.hpp"
#include "forest/core/frustum.hpp"
#include "forest/core/near_slab.hpp"
#include "forest/culling/occlusion_culler.hpp"
#include "query_batches.hpp"

namespace forest::culling {

// Visible without a query (CHC++ §3.6): the box holds the eye (grown by z_n), or meets the near
// slab, where the near plane could clip the faces its query needs (NearSlab).
inline bool boxVisibleWithoutQuery(const Aabb& box, const Camera& camera, const NearSlab& nearSlab) {
  const Aabb grown{box.min - glm::dvec3(camera.near), box.max + glm::dvec3(camera.near)};
  return grown.contains(camera.position) || nearSlab.meets(box);
}

// Eye-space depth range of a box's corners.
inline std::pair<double, double> depthRange(const Aabb& box, const glm::dmat4& view) {
  double nearest = std::numeric_limits<double>::infinity(), farthest = -nearest;
  for (int c = 0; c < 8; ++c) {
    const double depth = -(view * glm::dvec4(box.corner(c), 1.0)).z;
    nearest = std::min(nearest, depth);
    farthest = std::max(farthest, depth);
  }
  return {nearest, farthest};
}

// Traversal queue entry: nearest first.
struct Entry {
  double distance;
  std::int32_t node;
  bool operator<(const Entry& other) const { return distance > other.distance; }
};

// A nearest-first queue over a vector the culler keeps (std::priority_queue would own it).
struct EntryHeap {
  std::vector<Entry> items;
  bool empty() const { return items.empty(); }
  const Entry& top() const { return items.front(); }
  void push(const Entry& e) {
    items.push_back(e);
    std::push_heap(items.begin(), items.end());
  }
  void pop() {
    std::pop_heap(items.begin(), items.end());
    items.pop_back();
  }
};

// A first-in, first-out queue over a vector: popping moves a head index, clear() empties it; the
// storage stays (std::deque frees and allocates blocks as it goes).
template <class T>
struct FifoQueue {
  std::vector<T> items;
  std::size_t head = 0;
  bool empty() const { return head == items.size(); }
  T& front() { return items[head]; }
  void push(const T& v) { items.push_back(v); }
  void pop() {
    if (++head == items.size()) clear();
  }
  void clear() {
    items.clear();
    head = 0;
  }
};

// A query waiting for its result: CHC's single node, or CHC++'s group of nodes (a multiquery),
// `count` entries of TraversalScratch::groupNodes from `first`.
struct PendingQuery {
  std::size_t first = 0, count = 0;
  std::size_t slot = 0;
  bool drawnAlready = false;  // a visible leaf's query: drawn this frame, asks about the next
  int step = 0;               // traversal step at which it was issued (CHC's batches)
  bool geometry = false;      // drawn with the leaf's own triangles (chc++'s geometry queries)
  bool late = false;          // chc++: asked after the traversal's last draw (lateQueue)
};

// Every list the traversals use, kept by the culler so a steady-state frame allocates nothing.
struct TraversalScratch {
  EntryHeap traversal;
  std::vector<std::int32_t> stack;
  FifoQueue<PendingQuery> pending;
  std::vector<std::int32_t> groupNodes;  // the nodes of the pending queries
  std::vector<std::int32_t> invisibleQueue, visibleQueue, renderQueue, group;
  std::vector<std::int32_t> geometryQueue;  // chc++: leaves waiting for a geometry query
  std::vector<std::int32_t> confirmQueue;   // chc++: leaves found visible this frame, asked again at its end
  std::vector<std::int32_t> lateQueue;      // chc++: leaves hidden since their confirming query failed, asked at its end
  std::vector<std::int32_t> level, next, best;  // chc++'s tight query boxes
  std::vector<std::tuple<int, int, std::int32_t>> order;  // chc++: the i-queue sorted by p_keep
  std::vector<std::uint32_t> drawList;  // chc++: the render queue's objects
  std::vector<Aabb> boxes;
  // Room for the largest frame a BVH of `nodes` nodes over `objects` objects can make: each node
  // is queued, opened and queried at most four times (a multiquery, then on its own, then a
  // leaf with its own triangles, then once drawn), each object drawn and marked visible at most
  // twice; so no frame grows a list.
  void reserve(std::size_t nodes, std::size_t objects, std::size_t shapeBoxes, std::vector<std::uint32_t>& visible) {
    for (auto* v : {&stack, &invisibleQueue, &visibleQueue, &renderQueue, &geometryQueue, &confirmQueue, &lateQueue, &group, &level, &next, &best})
      v->reserve(2 * nodes);
    traversal.items.reserve(2 * nodes);
    pending.items.reserve(4 * nodes);
    groupNodes.reserve(4 * nodes);
    order.reserve(2 * nodes);
    boxes.reserve(2 * (nodes + shapeBoxes));
    drawList.reserve(2 * objects);
    visible.reserve(2 * objects);
  }
  void clear() {
    traversal.items.clear();
    stack.clear();
    pending.clear();
    groupNodes.clear();
    for (auto* v : {&invisibleQueue, &visibleQueue, &renderQueue, &geometryQueue, &confirmQueue, &lateQueue, &group}) v->clear();
  }
};

// The queries of parts of the objects a traversal draws (QueriesAfterTraversal: the terrain's
// blocks), asked on the culler's behalf during (chc++) and after the traversal
// (queries_after_cull.cpp).
class PartQueries {
 public:
  // A cull's start: `after` (may be null) is asked through `culler`, whose queries go out in
  // `queries`' batches.
  void start(OcclusionCuller& culler, QueryBatches& queries, QueriesAfterTraversal* after);
  // chc++: after a draw that comes before a batch of queries, while no earlier issueDuring's
  // results are untaken: QueriesAfterTraversal::issueDuring.
  void issueDuring();
  // Once those results are readable (`wait`: waiting for them if need be), before the next draw
  // or query: QueriesAfterTraversal::takeDuring, its triangles counted in stats.
  void takeDuring(CullingStats& stats, bool wait);
  // Once per cull, after its last draw (chc++: before its last wait; the other strategies: at
  // the end of the cull): QueriesAfterTraversal::issue.
  void issueAfter();

 private:
  OcclusionCuller* culler_ = nullptr;
  QueryBatches* queries_ = nullptr;
  QueriesAfterTraversal* after_ = nullptr;  // the current cull's, until issued
  bool duringIssued_ = false;  // issueDuring issued queries whose results are not taken
  std::size_t duringEnd_ = 0;  // the slots below this one hold them
};

// What one cull hands its strategy: the hierarchy, the view, where to draw and query, where the
// results go, and the scratch lists.
struct Traversal {
  const Bvh& bvh;
  const Camera& camera;
  Frustum frustum;
  ObjectDrawer& drawer;
  CullingStats& stats;
  std::vector<std::uint32_t>& visible;  // objects of the leaves found visible (may repeat)
  TraversalScratch& scratch;
  const QueryShapes& shapes;
  const CullingSettings& settings;  // the chc++ parameters ([culling])
  NearSlab nearSlab;                // of camera
  QueryBatches& queries;
  PartQueries& parts;
  std::uint64_t frame;  // the culler's frame number, from 1
  // Which objects had a pixel in the last image (OcclusionCuller::setShownInLastImage); empty
  // when not known.
  std::span<const std::uint8_t> shownInLastImage;

  // Draws the objects: the queries issued before them go out first, testing the depth without them.
  void drawObjects(std::span<const std::uint32_t> objects) {
    if (objects.empty()) return;
    queries.drawBatch(stats);
    queries.endQueryState();
    stats.trianglesDrawn += drawer.draw(objects);
    stats.objectsDrawn += static_cast<int>(objects.size());
    ++stats.drawCalls;
  }
  const std::vector<BvhNode>& nodes() const { return bvh.nodes(); }
  std::span<const std::uint32_t> objectsOf(std::int32_t n) const {
    const BvhNode& node = bvh.nodes()[n];
    return {bvh.objects().data() + node.first, node.count};
  }
  void markVisible(std::int32_t n) {
    const auto objects = objectsOf(n);
    visible.insert(visible.end(), objects.begin(), objects.end());
  }
  // What a query of node n draws: a leaf's objects' query shapes when there are some and their
  // total surface area is at most tight_box_area_ratio × the leaf box's (each box drawn costs its
  // rasterised area: CHC++ §3.5's rule for tighter boxes), else the node's box.
  void appendQueryBoxes(std::int32_t n, std::vector<Aabb>& out) const {
    const BvhNode& node = bvh.nodes()[n];
    if (!node.leaf() || shapes.empty()) {
      out.push_back(node.bounds);
      return;
    }
    double area = 0.0;
    for (std::uint32_t o : objectsOf(n))
      for (std::uint32_t k = 0; k < shapes.ranges[o].count; ++k) area += surfaceArea(shapes.boxes[shapes.ranges[o].first + k]);
    if (area > settings.tight_box_area_ratio * surfaceArea(node.bounds)) {
      out.push_back(node.bounds);
      return;
    }
    for (std::uint32_t o : objectsOf(n)) {
      const auto first = shapes.boxes.begin() + shapes.ranges[o].first;
      out.insert(out.end(), first, first + shapes.ranges[o].count);
    }
  }
  Entry entry(std::int32_t n) const { return {bvh.nodes()[n].bounds.distanceTo(camera.position), n}; }
  // Visible without a query (§3.6): the box holds the eye (grown by z_n), or meets the near slab,
  // where the near plane could clip the faces its query needs (NearSlab).
  bool visibleWithoutQuery(std::int32_t n) const { return boxVisibleWithoutQuery(bvh.nodes()[n].bounds, camera, nearSlab); }
};

// Marks node n and its not yet visible ancestors visible (CHC's pull-up): the node itself always
// (it may still carry last frame's flag), then its ancestors up to the first one already visible
// this frame (the ones opened this frame were reset to invisible). `State` has a `visible` flag.
template <class State>
void pullUpVisibility(const std::vector<BvhNode>& nodes, std::vector<State>& state, std::int32_t n) {
  state[n].visible = true;
  for (n = nodes[n].parent; n >= 0 && !state[n].visible; n = nodes[n].parent) state[n].visible = true;
}

// One culling strategy (OcclusionCuller's table names each): what it keeps of earlier frames per
// node, and one frame's traversal.
class TraversalStrategy {
 public:
  virtual ~TraversalStrategy() = default;
  // One frame: traverses t.bvh inside t.frustum, draws what it finds visible (t.drawObjects) and
  // adds the objects of the leaves it found visible to t.visible.
  virtual void traverse(Traversal& t) = 0;
  // Forgets what it kept of earlier frames (a BVH rebuild, a camera cut).
  virtual void forget() {}
};

// What the coherent strategies (CHC, CHC++) keep of a node from one frame to the next.
struct CoherentNodeState {
  bool visible = false;
  std::uint64_t lastVisited = 0;  // the frame that last took the node from the traversal queue
};

// A strategy that keeps a State per BVH node: fresh for a BVH of another size, gone when forgotten.
template <class State>
class StrategyWithNodeState : public TraversalStrategy {
 public:
  void forget() override { state_.clear(); }

 protected:
  // Sizes the state to the traversal's BVH (fresh for a BVH of another size).
  void fitStateTo(const Traversal& t) {
    if (state_.size() != t.nodes().size()) state_.assign(t.nodes().size(), State{});
  }
  std::vector<State> state_;
};

std::unique_ptr<TraversalStrategy> makeFrustumCulling(bool frustum);  // none (false) and frustum
std::unique_ptr<TraversalStrategy> makeStopAndWait();
std::unique_ptr<TraversalStrategy> makeChc();
std::unique_ptr<TraversalStrategy> makeChcPlusPlus();

}  // namespace forest::culling
