// stop-and-wait: front to back, each node in the frustum queried and its result waited for before
// the traversal goes on (the baseline CHC is measured against: Bittner et al. 2004, §3). Nothing is
// kept from frame to frame.
#include "traversal.hpp"

namespace forest::culling {
namespace {

class StopAndWait final : public TraversalStrategy {
 public:
  void traverse(Traversal& t) override {
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
        const std::size_t slot = t.queries.issueBoxes(t.scratch.boxes);
        ++t.stats.queriesIssued;
        isVisible = t.queries.waitResult(slot, t.stats);
      }
      if (!isVisible) continue;
      if (nodes[n].leaf()) {
        t.drawObjects(t.objectsOf(n));
        t.markVisible(n);
      } else {
        traversal.push(t.entry(nodes[n].left));
        traversal.push(t.entry(nodes[n].right));
      }
    }
  }
};

}  // namespace

std::unique_ptr<TraversalStrategy> makeStopAndWait() { return std::make_unique<StopAndWait>(); }

}  // namespace forest::culling
