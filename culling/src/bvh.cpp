#include "forest/culling/bvh.hpp"

#include <algorithm>
#include <limits>
#include <numeric>

#include "forest/core/error.hpp"

namespace forest::culling {

double surfaceArea(const Aabb& box) {
  if (!box.valid()) return 0.0;
  const glm::dvec3 e = box.extent();
  return 2.0 * (e.x * e.y + e.y * e.z + e.z * e.x);
}

Bvh::Bvh(std::span<const Aabb> boxes, int leafSize) : leafSize_(leafSize) {
  if (leafSize < 1) throw InputError("culling: BVH leaf size must be at least 1, got " + std::to_string(leafSize));
  build(boxes);
}

void Bvh::build(std::span<const Aabb> boxes) {
  nodes_.clear();
  objects_.resize(boxes.size());
  std::iota(objects_.begin(), objects_.end(), 0u);
  if (!boxes.empty()) buildRange(boxes, 0, static_cast<std::uint32_t>(boxes.size()), -1);
  builtCost_ = sahCost();
}

// Top-down SAH (MacDonald & Booth 1990): on each axis, objects sorted by centroid; the split
// minimising area(left)·n(left) + area(right)·n(right) wins. A range of at most leafSize objects
// is a leaf: the leaf size is what a query decides for (one tree by default, DESIGN §4), not
// left to the SAH, which would split every pair of trees apart anyway.
std::int32_t Bvh::buildRange(std::span<const Aabb> boxes, std::uint32_t first, std::uint32_t count, std::int32_t parent) {
  const std::int32_t index = static_cast<std::int32_t>(nodes_.size());
  nodes_.emplace_back();
  nodes_[index].parent = parent;
  Aabb bounds;
  for (std::uint32_t i = first; i < first + count; ++i) bounds.extend(boxes[objects_[i]]);
  nodes_[index].bounds = bounds;
  auto makeLeaf = [&] {
    nodes_[index].first = first;
    nodes_[index].count = count;
    return index;
  };
  if (count <= static_cast<std::uint32_t>(leafSize_)) return makeLeaf();

  const auto begin = objects_.begin() + first, end = begin + count;
  double bestCost = std::numeric_limits<double>::infinity();
  int bestAxis = -1;
  std::uint32_t bestSplit = 0;
  std::vector<double> rightArea(count);
  for (int axis = 0; axis < 3; ++axis) {
    std::sort(begin, end, [&](std::uint32_t a, std::uint32_t b) {
      const double ca = boxes[a].min[axis] + boxes[a].max[axis], cb = boxes[b].min[axis] + boxes[b].max[axis];
      return ca < cb || (ca == cb && a < b);
    });
    Aabb right;
    for (std::uint32_t k = count; k-- > 1;) {
      right.extend(boxes[objects_[first + k]]);
      rightArea[k] = surfaceArea(right);
    }
    Aabb left;
    for (std::uint32_t k = 1; k < count; ++k) {
      left.extend(boxes[objects_[first + k - 1]]);
      const double cost = surfaceArea(left) * k + rightArea[k] * (count - k);
      if (cost < bestCost) {
        bestCost = cost;
        bestAxis = axis;
        bestSplit = k;
      }
    }
  }
  std::sort(begin, end, [&](std::uint32_t a, std::uint32_t b) {
    const double ca = boxes[a].min[bestAxis] + boxes[a].max[bestAxis], cb = boxes[b].min[bestAxis] + boxes[b].max[bestAxis];
    return ca < cb || (ca == cb && a < b);
  });
  const std::int32_t left = buildRange(boxes, first, bestSplit, index);
  const std::int32_t right = buildRange(boxes, first + bestSplit, count - bestSplit, index);
  nodes_[index].left = left;
  nodes_[index].right = right;
  return index;
}

double Bvh::sahCost() const {
  if (nodes_.empty()) return 0.0;
  const double rootArea = std::max(surfaceArea(nodes_[0].bounds), 1e-300);
  double cost = 0.0;
  for (const BvhNode& n : nodes_) cost += surfaceArea(n.bounds) / rootArea * (n.leaf() ? n.count : 1.0);
  return cost;
}

bool Bvh::refit(std::span<const Aabb> boxes) {
  if (boxes.size() != objects_.size())
    throw Error("Bvh::refit: " + std::to_string(boxes.size()) + " boxes for " + std::to_string(objects_.size()) + " objects");
  // Children follow their parent in the node array: one backward sweep updates every box.
  for (std::size_t i = nodes_.size(); i-- > 0;) {
    BvhNode& n = nodes_[i];
    Aabb b;
    if (n.leaf()) {
      for (std::uint32_t k = n.first; k < n.first + n.count; ++k) b.extend(boxes[objects_[k]]);
    } else {
      b = nodes_[n.left].bounds;
      b.extend(nodes_[n.right].bounds);
    }
    n.bounds = b;
  }
  if (sahCost() > kRebuildCostRatio * builtCost_) {
    build(boxes);
    return true;
  }
  return false;
}

}  // namespace forest::culling
