// CHC: coherent hierarchical culling (Bittner, Wimmer, Piringer, Purgathofer, EG 2004, fig. 4).
// Previously visible leaves are drawn at once and queried for the next frame, previously visible
// interior nodes are opened without a query, previously invisible nodes are queried and opened
// only when their result says visible; traversal goes on while results are pending, and a visible
// result pulls visibility up to the root.
#include "traversal.hpp"

namespace forest::culling {
namespace {

// Deterministic mode takes CHC's query results at batch boundaries, every kBatchSteps traversal
// steps: the queries issued before the previous boundary are taken (waiting if need be), the newer
// ones stay pending while traversal and drawing go on. Taking results at fixed points, not whenever
// the driver happens to have them, makes the traversal — and so the visible set, z_f and the
// shadows — identical from run to run; polling for availability would also flush llvmpipe's
// command stream.
constexpr int kBatchSteps = 64;

class Chc final : public StrategyWithNodeState<CoherentNodeState> {
 public:
  void traverse(Traversal& t) override;

 private:
  // A leaf is drawn, an interior node's children are queued.
  void traverseNode(Traversal& t, std::int32_t n) {
    if (t.nodes()[n].leaf()) {
      t.drawObjects(t.objectsOf(n));
    } else {
      t.scratch.traversal.push(t.entry(t.nodes()[n].left));
      t.scratch.traversal.push(t.entry(t.nodes()[n].right));
    }
  }
  // A query's result: a visible node pulls visibility up, and is traversed unless it was a
  // previously visible leaf (drawn already, queried for the next frame).
  void handleResult(Traversal& t, const PendingQuery& p, bool visible) {
    if (!visible) return;
    const std::int32_t node = static_cast<std::int32_t>(p.first);
    pullUpVisibility(t.nodes(), state_, node);
    if (t.nodes()[node].leaf()) t.markVisible(node);
    if (!p.drawnAlready) traverseNode(t, node);
  }
  // Results: all when nothing is left to traverse; else deterministic: at each batch boundary
  // those issued a batch ago; async: whichever the GPU has finished (fig. 4).
  bool resultReady(Traversal& t, int steps) const {
    if (t.scratch.traversal.empty()) return true;
    if (t.queries.mode() == QueryMode::Async) return t.queries.resultAvailable(t.scratch.pending.front().slot, t.stats);
    return steps % kBatchSteps == 0 && t.scratch.pending.front().step <= steps - kBatchSteps;
  }
  void visit(Traversal& t, std::int32_t n, int steps);
};

// A node taken from the traversal queue inside the frustum.
void Chc::visit(Traversal& t, std::int32_t n, int steps) {
  ++t.stats.nodesVisited;
  CoherentNodeState& s = state_[n];
  if (t.visibleWithoutQuery(n)) {
    s.lastVisited = t.frame;
    pullUpVisibility(t.nodes(), state_, n);
    if (t.nodes()[n].leaf()) t.markVisible(n);
    traverseNode(t, n);
    return;
  }
  const bool wasVisible = s.visible && s.lastVisited + 1 == t.frame;
  const bool opened = wasVisible && !t.nodes()[n].leaf();
  s.visible = false;
  s.lastVisited = t.frame;
  if (!opened) {
    t.scratch.boxes.clear();
    t.appendQueryBoxes(n, t.scratch.boxes);
    // Each pending query holds one node (first); drawnAlready: a previously visible leaf.
    t.scratch.pending.push({static_cast<std::size_t>(n), 1, t.queries.issueBoxes(t.scratch.boxes), wasVisible, steps});
    ++t.stats.queriesIssued;
  }
  if (wasVisible) traverseNode(t, n);
}

void Chc::traverse(Traversal& t) {
  const std::vector<BvhNode>& nodes = t.nodes();
  fitStateTo(t);
  EntryHeap& traversal = t.scratch.traversal;
  FifoQueue<PendingQuery>& queries = t.scratch.pending;
  if (!nodes.empty()) traversal.push(t.entry(0));
  int steps = 0;
  while (!traversal.empty() || !queries.empty()) {
    while (!queries.empty() && resultReady(t, steps)) {
      const PendingQuery p = queries.front();
      queries.pop();
      handleResult(t, p, t.queries.waitResult(p.slot, t.stats));
    }
    if (traversal.empty()) continue;
    ++steps;
    const std::int32_t n = traversal.top().node;
    traversal.pop();
    if (t.frustum.mayIntersect(nodes[n].bounds)) visit(t, n, steps);
  }
}

}  // namespace

std::unique_ptr<TraversalStrategy> makeChc() { return std::make_unique<Chc>(); }

}  // namespace forest::culling
