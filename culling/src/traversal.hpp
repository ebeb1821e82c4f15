#pragma once
// One culling frame's shared state and the helpers every traversal strategy uses (internal).
#include <fmt/format.h>
#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>
#include <tuple>
#include <utility>
#include <vector>

#include "forest/core/error.hpp"
#include "forest/core/frustum.hpp"
#include "forest/core/near_slab.hpp"
#include "forest/culling/occlusion_culler.hpp"

namespace forest::culling {

// Visible without a query (CHC++ §3.6): the box holds the eye (grown by z_n), or meets the near
// slab, where the near plane could clip the faces its query needs (NearSlab).
inline bool boxVisibleWithoutQuery(const Aabb& box, const Camera& camera, const NearSlab& nearSlab) {
  const Aabb grown{box.min - glm::dvec3(camera.near), box.max + glm::dvec3(camera.near)};
  return grown.contains(camera.position) || nearSlab.meets(box);
}

// CHC's query results are collected at batch boundaries, every kBatchSteps traversal steps: the
// queries issued before the previous boundary are taken (waiting if need be), the newer ones stay
// pending while traversal and drawing go on. Taking results at fixed points, not whenever the
// driver happens to have them, makes the traversal — and so the visible set, z_f and the shadows —
// identical from run to run; polling for availability would also flush llvmpipe's command stream.
constexpr int kBatchSteps = 64;

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

// At most 3N + 1 per frame for a BVH of N nodes: a node enters the traversal once, and is queried
// once for itself, once more when a multiquery that held it found something; a leaf also once
// with its own triangles (its geometry query) and, found visible, once more after the frame is
// drawn (chc++'s c-queue). With L leaves and L − 1 inner nodes that is 4L + 2(L − 1) = 3N + 1.
inline std::uint32_t takeSlot(std::size_t& used, std::size_t slots) {
  if (used == slots) throw Error(fmt::format("OcclusionCuller: more than {} queries in a frame", slots));
  return static_cast<std::uint32_t>(used++);
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
// `count` entries of Scratch::groupNodes from `first`.
struct PendingQuery {
  std::size_t first = 0, count = 0;
  std::size_t slot = 0;
  bool drawnAlready = false;  // a visible leaf's query: drawn this frame, asks about the next
  int step = 0;               // traversal step at which it was issued (CHC's batches)
  bool geometry = false;      // drawn with the leaf's own triangles (chc++'s geometry queries)
  bool late = false;          // chc++: asked after the traversal's last draw (lateQueue)
};

// Every list the traversals use, kept by the culler so a steady-state frame allocates nothing.
struct OcclusionCuller::Scratch {
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

struct OcclusionCuller::Traversal {
  const Bvh& bvh;
  const Camera& camera;
  Frustum frustum;
  ObjectDrawer& drawer;
  CullingStats& stats;
  std::vector<std::uint32_t>& visible;  // objects of the leaves found visible (may repeat)
  Scratch& scratch;
  const QueryShapes& shapes;
  double shapeAreaRatio;  // the chc++ tight-box rule (§3.5): shapes only when their area ≤ this × the box's
  NearSlab nearSlab;      // of camera

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
  // total surface area is at most shapeAreaRatio × the leaf box's (each box drawn costs its
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
    if (area > shapeAreaRatio * surfaceArea(node.bounds)) {
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

}  // namespace forest::culling
