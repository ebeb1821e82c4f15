#include "forest/culling/bvh.hpp"

#include <algorithm>
#include <array>
#include <limits>
#include <numeric>

#include "forest/core/error.hpp"
#include "forest/core/parallel.hpp"

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
  if (!boxes.empty()) buildRange(nodes_, boxes, 0, static_cast<std::uint32_t>(boxes.size()), -1, kForkLevels);
  builtCost_ = sahCost();
}

namespace {
// Appends `part` (a subtree built on its own, its root at 0) to `nodes`, its root's parent
// `parent`; returns the root's index. Preorder is kept: the same array as building it in place.
std::int32_t splice(std::vector<BvhNode>& nodes, const std::vector<BvhNode>& part, std::int32_t parent) {
  const std::int32_t offset = static_cast<std::int32_t>(nodes.size());
  for (BvhNode node : part) {
    node.parent = node.parent < 0 ? parent : node.parent + offset;
    if (!node.leaf()) {
      node.left += offset;
      node.right += offset;
    }
    nodes.push_back(node);
  }
  return offset;
}
}  // namespace

// Top-down SAH (MacDonald & Booth 1990): the split minimising area(left)·n(left) +
// area(right)·n(right). A range of at most leafSize objects is a leaf: the leaf size is what a
// query decides for (one tree by default, DESIGN §4), not left to the SAH, which would split every
// pair of trees apart anyway. Ranges of more than kBinnedSahAbove objects (a landscape's upper
// levels) are split by binned SAH, the rest by the exact sweep.
// The two halves of a range of more than kBinnedSahAbove objects, `forks` levels down from the
// root, are built at once on threads of their own (their objects are disjoint ranges of objects_),
// each into its own node list, then spliced in preorder: the array serial building makes.
std::int32_t Bvh::buildRange(std::vector<BvhNode>& nodes, std::span<const Aabb> boxes, std::uint32_t first, std::uint32_t count,
                             std::int32_t parent, int forks) {
  const std::int32_t index = static_cast<std::int32_t>(nodes.size());
  nodes.emplace_back();
  nodes[index].parent = parent;
  Aabb bounds;
  for (std::uint32_t i = first; i < first + count; ++i) bounds.extend(boxes[objects_[i]]);
  nodes[index].bounds = bounds;
  if (count <= static_cast<std::uint32_t>(leafSize_)) {
    nodes[index].first = first;
    nodes[index].count = count;
    return index;
  }
  const std::uint32_t split = count > kBinnedSahAbove ? binnedSplit(boxes, first, count) : sweepSplit(boxes, first, count);
  if (forks > 0 && count > kBinnedSahAbove) {
    std::array<std::vector<BvhNode>, 2> halves;
    parallelFor(2, [&](int half) {
      buildRange(halves[static_cast<size_t>(half)], boxes, half == 0 ? first : first + split, half == 0 ? split : count - split, -1,
                 forks - 1);
    });
    nodes[index].left = splice(nodes, halves[0], index);
    nodes[index].right = splice(nodes, halves[1], index);
    return index;
  }
  const std::int32_t left = buildRange(nodes, boxes, first, split, index, forks);
  const std::int32_t right = buildRange(nodes, boxes, first + split, count - split, index, forks);
  nodes[index].left = left;
  nodes[index].right = right;
  return index;
}

// On each axis, the objects sorted by centroid; every split between neighbours is costed.
std::uint32_t Bvh::sweepSplit(std::span<const Aabb> boxes, std::uint32_t first, std::uint32_t count) {
  const auto begin = objects_.begin() + first, end = begin + count;
  double bestCost = std::numeric_limits<double>::infinity();
  int bestAxis = 0;
  std::uint32_t bestSplit = count / 2;
  std::vector<double> rightArea(count);
  const auto byCentroid = [&](int axis) {
    return [&boxes, axis](std::uint32_t a, std::uint32_t b) {
      const double ca = boxes[a].min[axis] + boxes[a].max[axis], cb = boxes[b].min[axis] + boxes[b].max[axis];
      return ca < cb || (ca == cb && a < b);
    };
  };
  for (int axis = 0; axis < 3; ++axis) {
    std::sort(begin, end, byCentroid(axis));
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
  std::sort(begin, end, byCentroid(bestAxis));
  return bestSplit;
}

// Binned SAH (Wald, "On fast construction of SAH-based bounding volume hierarchies", 2007): the
// centroids' range on each axis cut into kSahBins equal bins; the kSahBins − 1 planes between bins
// are costed from the bins' boxes and counts. Where every centroid coincides, a median split.
std::uint32_t Bvh::binnedSplit(std::span<const Aabb> boxes, std::uint32_t first, std::uint32_t count) {
  const auto begin = objects_.begin() + first, end = begin + count;
  Aabb centroids;
  for (auto it = begin; it != end; ++it) centroids.extend(boxes[*it].centre());
  struct Bin {
    Aabb box;
    std::uint32_t count = 0;
  };
  double bestCost = std::numeric_limits<double>::infinity();
  int bestAxis = -1, bestPlane = 0;
  const auto binOf = [&](std::uint32_t object, int axis) {
    const double lo = centroids.min[axis], width = centroids.max[axis] - lo;
    return std::min(static_cast<int>((boxes[object].centre()[axis] - lo) / width * kSahBins), kSahBins - 1);
  };
  for (int axis = 0; axis < 3; ++axis) {
    if (!(centroids.max[axis] > centroids.min[axis])) continue;
    std::array<Bin, kSahBins> bins;
    for (auto it = begin; it != end; ++it) {
      Bin& bin = bins[static_cast<size_t>(binOf(*it, axis))];
      bin.box.extend(boxes[*it]);
      ++bin.count;
    }
    std::array<double, kSahBins> rightCost{};  // rightCost[p]: the bins from p on
    Aabb right;
    std::uint32_t rightCount = 0;
    for (int p = kSahBins; p-- > 1;) {
      right.extend(bins[static_cast<size_t>(p)].box);
      rightCount += bins[static_cast<size_t>(p)].count;
      rightCost[static_cast<size_t>(p)] = surfaceArea(right) * rightCount;
    }
    Aabb left;
    std::uint32_t leftCount = 0;
    for (int p = 1; p < kSahBins; ++p) {
      left.extend(bins[static_cast<size_t>(p - 1)].box);
      leftCount += bins[static_cast<size_t>(p - 1)].count;
      const double cost = surfaceArea(left) * leftCount + rightCost[static_cast<size_t>(p)];
      if (leftCount > 0 && leftCount < count && cost < bestCost) {
        bestCost = cost;
        bestAxis = axis;
        bestPlane = p;
      }
    }
  }
  if (bestAxis < 0) return count / 2;  // one point: any split is as good
  const auto middle = std::stable_partition(begin, end, [&](std::uint32_t o) { return binOf(o, bestAxis) < bestPlane; });
  return static_cast<std::uint32_t>(middle - begin);
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
