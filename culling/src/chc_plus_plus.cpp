// CHC++ (Mattausch, Bittner, Wimmer: "CHC++: Coherent Hierarchical Culling Revisited", EG 2008).
// Deterministic mode takes results at fixed traversal steps (kBatchSteps), never by polling, so
// that a run traverses — and so draws and queries — the same way every time; async mode takes each
// result as soon as GL_QUERY_RESULT_AVAILABLE says so, as the paper does.
#include <algorithm>
#include <cmath>
#include <deque>
#include <queue>

#include "traversal.hpp"

namespace forest::culling {
namespace {

// §3.4: the probability that a node found invisible for i frames in a row stays invisible.
double keepProbability(int invisibleFrames) { return 0.99 - 0.7 * std::exp(-static_cast<double>(invisibleFrames)); }

// A deterministic draw in [0, n) per (node, frame): the random first re-query interval (§3.3).
std::uint64_t hashDraw(std::uint64_t node, std::uint64_t frame, std::uint64_t n) {
  std::uint64_t x = node * 0x9E3779B97F4A7C15ull ^ (frame + 0x632BE59BD9B4E019ull);
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;  // splitmix64 finaliser
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return (x ^ (x >> 31)) % n;
}

// §3.5: the boxes a node's query draws — its descendants `depth` levels down (leaves above that
// depth count as themselves) when their total area is at most `ratio` × the node box's, trying
// the deepest level first; else the node's own box. The union holds all of the node's geometry,
// so a hidden result stays exact.
void queryBoxes(const std::vector<BvhNode>& nodes, std::int32_t node, int depth, double ratio, std::vector<Aabb>& out) {
  const double limit = ratio * surfaceArea(nodes[node].bounds);
  std::vector<std::int32_t> level{node}, best{node};
  for (int d = 1; d <= depth; ++d) {
    std::vector<std::int32_t> next;
    for (std::int32_t n : level) {
      if (nodes[n].leaf()) {
        next.push_back(n);
      } else {
        next.push_back(nodes[n].left);
        next.push_back(nodes[n].right);
      }
    }
    if (next.size() == level.size()) break;  // only leaves left
    double area = 0.0;
    for (std::int32_t n : next) area += surfaceArea(nodes[n].bounds);
    if (area <= limit) best = next;
    level = std::move(next);
  }
  for (std::int32_t n : best) out.push_back(nodes[n].bounds);
}

}  // namespace

void OcclusionCuller::cullChcPlusPlus(Traversal& t) {
  const std::vector<BvhNode>& nodes = t.nodes();
  const CullingSettings& p = parameters_;
  const std::uint64_t requery = static_cast<std::uint64_t>(std::max(1, p.visible_requery_frames));
  struct Pending {
    std::vector<std::int32_t> nodes;  // several: a multiquery
    std::size_t slot;
    bool drawnAlready;  // a visible leaf's query (v-queue): drawn this frame, asks about the next
    int step;           // traversal step at which it was issued
  };
  std::priority_queue<Entry> traversal;
  std::deque<Pending> pending;
  std::vector<std::int32_t> invisibleQueue, visibleQueue, renderQueue;
  std::vector<std::uint32_t> objects;
  std::vector<Aabb> boxes;
  int steps = 0;

  // §3.2: visible leaves wait in the render queue; it is drawn in one call before any query goes
  // out (the depth buffer must hold everything known visible) and at the end.
  auto flushRender = [&] {
    objects.clear();
    for (std::int32_t n : renderQueue) {
      const auto o = t.objectsOf(n);
      objects.insert(objects.end(), o.begin(), o.end());
    }
    renderQueue.clear();
    drawObjects(t, objects);
  };
  auto issue = [&](std::vector<std::int32_t> group, bool drawnAlready) {
    boxes.clear();
    for (std::int32_t n : group) queryBoxes(nodes, n, p.tight_box_depth, p.tight_box_area_ratio, boxes);
    ++t.stats.queriesIssued;
    if (group.size() > 1) ++t.stats.multiQueries;
    const std::size_t slot = issueQuery(boxes);
    pending.push_back({std::move(group), slot, drawnAlready, steps});
  };
  // §3.1, §3.4: the i-queue goes out as one batch; with multiqueries, nodes sorted by p_keep are
  // grouped greedily while the group's queries saved per query issued, |M| / (1 + (1 − Π p)·|M|),
  // grows (a single node is an ordinary query: cost 1).
  auto issueInvisibleQueue = [&] {
    if (invisibleQueue.empty()) return;
    flushRender();
    if (!p.multiqueries) {
      for (std::int32_t n : invisibleQueue) issue({n}, false);
      invisibleQueue.clear();
      return;
    }
    std::stable_sort(invisibleQueue.begin(), invisibleQueue.end(),
                     [&](std::int32_t a, std::int32_t b) { return state_[a].invisibleFrames > state_[b].invisibleFrames; });
    auto value = [](double keepAll, size_t size) {
      return size <= 1 ? static_cast<double>(size) : static_cast<double>(size) / (1.0 + (1.0 - keepAll) * static_cast<double>(size));
    };
    std::vector<std::int32_t> group;
    double keepAll = 1.0;
    for (std::int32_t n : invisibleQueue) {
      const double keep = keepProbability(state_[n].invisibleFrames);
      if (!group.empty() && value(keepAll * keep, group.size() + 1) <= value(keepAll, group.size())) {
        issue(std::move(group), false);
        group.clear();
        keepAll = 1.0;
      }
      group.push_back(n);
      keepAll *= keep;
    }
    if (!group.empty()) issue(std::move(group), false);
    invisibleQueue.clear();
  };
  auto traverseNode = [&](std::int32_t n) {
    if (nodes[n].leaf()) {
      renderQueue.push_back(n);
    } else {
      traversal.push(t.entry(nodes[n].left));
      traversal.push(t.entry(nodes[n].right));
    }
  };
  auto foundInvisible = [&](std::int32_t n) {
    state_[n].visible = false;
    state_[n].invisibleFrames = std::min(state_[n].invisibleFrames + 1, 1000);
  };
  auto handleResult = [&](Pending& q, std::uint32_t samples) {
    if (q.nodes.size() > 1) {  // a multiquery: all hidden, or ask each node on its own
      if (samples == 0) {
        for (std::int32_t n : q.nodes) foundInvisible(n);
      } else {
        for (std::int32_t n : q.nodes) issue({n}, false);
      }
      return;
    }
    const std::int32_t n = q.nodes.front();
    if (samples == 0) {
      foundInvisible(n);
      return;
    }
    NodeState& s = state_[n];
    const bool wasInvisible = !q.drawnAlready;
    pullUpVisibility(n);
    s.invisibleFrames = 0;
    if (nodes[n].leaf()) {
      t.markVisible(n);
      if (wasInvisible) s.nextQueryFrame = frame_ + 1 + hashDraw(static_cast<std::uint64_t>(n), frame_, requery);  // §3.3
    }
    if (wasInvisible) traverseNode(n);
  };
  auto takeResult = [&] {
    Pending q = std::move(pending.front());
    pending.pop_front();
    handleResult(q, waitResult(q.slot, t.stats));
  };

  if (!nodes.empty()) traversal.push(t.entry(0));
  while (true) {
    // Results: deterministic, at each batch boundary those issued a batch ago; async, those the GPU
    // has finished.
    if (queryMode_ == QueryMode::Async) {
      while (!pending.empty() && resultAvailable(pending.front().slot, t.stats)) takeResult();
    } else if (steps % kBatchSteps == 0) {
      while (!pending.empty() && pending.front().step <= steps - kBatchSteps) takeResult();
    }
    if (traversal.empty()) {
      if (!invisibleQueue.empty()) {
        issueInvisibleQueue();
      } else if (!pending.empty()) {
        // About to wait: issue the visible leaves' queries first (§3.2), then take a result.
        if (!visibleQueue.empty()) {
          flushRender();
          for (std::int32_t n : visibleQueue) issue({n}, true);
          visibleQueue.clear();
        }
        takeResult();
      } else {
        break;
      }
      continue;
    }
    ++steps;
    const std::int32_t n = traversal.top().node;
    traversal.pop();
    if (!t.frustum.mayIntersect(nodes[n].bounds)) continue;
    ++t.stats.nodesVisited;
    NodeState& s = state_[n];
    const bool wasVisible = s.visible && s.lastVisited + 1 == frame_;
    s.lastVisited = frame_;
    if (t.visibleWithoutQuery(n)) {  // §3.6: the camera is in (or at) the box
      pullUpVisibility(n);
      s.invisibleFrames = 0;
      if (nodes[n].leaf()) t.markVisible(n);
      traverseNode(n);
      continue;
    }
    if (!wasVisible) {  // §3.1: wait in the i-queue for a batch
      s.visible = false;
      invisibleQueue.push_back(n);
      if (static_cast<int>(invisibleQueue.size()) >= p.batch_size) issueInvisibleQueue();
      continue;
    }
    if (!nodes[n].leaf()) {  // opened without a query; a visible descendant pulls visibility up again
      s.visible = false;
      traverseNode(n);
      continue;
    }
    // A visible leaf is drawn; it is queried again only every n_av frames (§3.3), else assumed visible.
    renderQueue.push_back(n);
    if (frame_ >= s.nextQueryFrame) {
      s.visible = false;
      s.nextQueryFrame = frame_ + requery;
      visibleQueue.push_back(n);
    } else {
      pullUpVisibility(n);
      t.markVisible(n);
    }
  }
  flushRender();
  // The remaining visible leaves' queries (for the next frame); their results complete this frame's state.
  for (std::int32_t n : visibleQueue) issue({n}, true);
  visibleQueue.clear();
  while (!pending.empty()) takeResult();
}

}  // namespace forest::culling
