#pragma once
// A bounding volume hierarchy over the scene's objects (terrain tiles, trees, props —
// anything with a box): the hierarchy coherent hierarchical culling traverses (Bittner et al.,
// EG 2004). Built top-down with the surface area heuristic over sorted centroids; refitted in
// place when objects move, rebuilt when refitting has degraded it past kRebuildCostRatio.
#include <cstdint>
#include <span>
#include <vector>

#include "forest/core/bounds.hpp"

namespace forest::culling {

struct BvhNode {
  Aabb bounds;
  std::int32_t parent = -1;
  std::int32_t left = -1, right = -1;  // children (interior nodes); -1 for leaves
  std::uint32_t first = 0, count = 0;  // leaves: range in Bvh::objects()
  bool leaf() const { return left < 0; }
};

// Refitting keeps the topology; once the SAH cost exceeds the build's by this factor (objects
// moved far from their neighbours), refit() rebuilds.
constexpr double kRebuildCostRatio = 1.5;
// Ranges of more objects than this are split by binned SAH into kSahBins bins per axis (a million
// trees: seconds less than sorting every range three times); smaller ones by the exact sweep, so
// scenes of a few thousand objects build as before.
constexpr std::uint32_t kBinnedSahAbove = 16384;
constexpr int kSahBins = 32;

class Bvh {
 public:
  Bvh() = default;
  // `leafSize`: objects per leaf, ≥ 1: a range of that many or fewer becomes a leaf.
  Bvh(std::span<const Aabb> objectBoxes, int leafSize);

  const std::vector<BvhNode>& nodes() const { return nodes_; }
  // Object indices in leaf order; leaf L holds objects()[L.first, L.first + L.count).
  const std::vector<std::uint32_t>& objects() const { return objects_; }
  int leafSize() const { return leafSize_; }
  std::size_t objectCount() const { return objects_.size(); }

  // Updates every box from the objects' new boxes (same count); rebuilds when the SAH cost
  // exceeds kRebuildCostRatio × the cost at the last build. Returns true if it rebuilt.
  bool refit(std::span<const Aabb> objectBoxes);
  // SAH cost: Σ over nodes of area(node) / area(root) × (1 for interior, count for leaves).
  double sahCost() const;

 private:
  void build(std::span<const Aabb> boxes);
  // Builds the range's subtree into `nodes` (preorder); `forks`: levels whose halves build at once.
  std::int32_t buildRange(std::vector<BvhNode>& nodes, std::span<const Aabb> boxes, std::uint32_t first, std::uint32_t count,
                          std::int32_t parent, int forks);
  static constexpr int kForkLevels = 2;  // up to 4 subtrees at once: two cores kept busy
  // The split of a range: the objects in [first, first + split) go left (they are reordered so).
  std::uint32_t sweepSplit(std::span<const Aabb> boxes, std::uint32_t first, std::uint32_t count);
  std::uint32_t binnedSplit(std::span<const Aabb> boxes, std::uint32_t first, std::uint32_t count);

  std::vector<BvhNode> nodes_;
  std::vector<std::uint32_t> objects_;
  int leafSize_ = 1;
  double builtCost_ = 0.0;
};

double surfaceArea(const Aabb& box);

}  // namespace forest::culling
