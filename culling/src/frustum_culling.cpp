// none (every object) and frustum culling of the hierarchy: the leaves inside, drawn in one call.
// Nothing is kept from frame to frame.
#include "traversal.hpp"

namespace forest::culling {
namespace {

class FrustumCulling final : public TraversalStrategy {
 public:
  explicit FrustumCulling(bool frustum) : frustum_(frustum) {}

  void traverse(Traversal& t) override {
    const std::vector<BvhNode>& nodes = t.nodes();
    std::vector<std::int32_t>& stack = t.scratch.stack;
    if (!nodes.empty()) stack.push_back(0);
    while (!stack.empty()) {
      const std::int32_t n = stack.back();
      stack.pop_back();
      if (frustum_ && !t.frustum.mayIntersect(nodes[n].bounds)) continue;
      ++t.stats.nodesVisited;
      if (nodes[n].leaf()) {
        t.markVisible(n);
      } else {
        stack.push_back(nodes[n].right);
        stack.push_back(nodes[n].left);
      }
    }
    std::sort(t.visible.begin(), t.visible.end());
    t.drawObjects(t.visible);
  }

 private:
  bool frustum_;  // false: none, every node
};

}  // namespace

std::unique_ptr<TraversalStrategy> makeFrustumCulling(bool frustum) { return std::make_unique<FrustumCulling>(frustum); }

}  // namespace forest::culling
