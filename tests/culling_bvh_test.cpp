// The culling BVH (culling/bvh.hpp), without GL: every object in exactly one leaf whose box holds
// it, every child inside its parent, after a build and after refits of moved boxes.
#include <gtest/gtest.h>
#include <glm/glm.hpp>

#include <cmath>
#include <cstdio>
#include <functional>
#include <cstdint>
#include <vector>

#include "forest/core/bounds.hpp"
#include "forest/core/error.hpp"
#include "forest/culling/bvh.hpp"

namespace forest {
namespace {

using glm::dvec3;

TEST(Bvh, EveryObjectInsideItsLeafAfterBuildAndRefit) {
  std::vector<Aabb> boxes;
  for (int k = 0; k < 300; ++k) {
    const dvec3 p(std::sin(k * 1.3) * 100.0, std::cos(k * 0.7) * 5.0, std::sin(k * 2.9) * 100.0);
    boxes.push_back({p, p + dvec3(1.0 + k % 3, 2.0, 1.0)});
  }
  for (int leafSize : {1, 4}) {
    culling::Bvh bvh(boxes, leafSize);
    auto check = [&] {
      std::vector<int> seen(boxes.size(), 0);
      for (const culling::BvhNode& n : bvh.nodes()) {
        if (!n.leaf()) {
          for (std::int32_t child : {n.left, n.right}) {
            EXPECT_TRUE(n.bounds.contains(bvh.nodes()[child].bounds.min) && n.bounds.contains(bvh.nodes()[child].bounds.max));
            EXPECT_EQ(bvh.nodes()[child].parent, &n - bvh.nodes().data());
          }
          continue;
        }
        EXPECT_LE(n.count, static_cast<std::uint32_t>(leafSize));
        for (std::uint32_t k = n.first; k < n.first + n.count; ++k) {
          const Aabb& b = boxes[bvh.objects()[k]];
          EXPECT_TRUE(n.bounds.contains(b.min) && n.bounds.contains(b.max));
          ++seen[bvh.objects()[k]];
        }
      }
      for (int s : seen) EXPECT_EQ(s, 1);
    };
    check();
    for (int round = 0; round < 5; ++round) {  // random moves, refit (and rebuild when degraded)
      for (int k = round; k < static_cast<int>(boxes.size()); k += 7) {
        const dvec3 shift(std::sin(k * 0.31 + round) * 60.0, 0.0, std::cos(k * 0.17 + round) * 60.0);
        boxes[k].min += shift;
        boxes[k].max += shift;
      }
      bvh.refit(boxes);
      check();
    }
  }
  EXPECT_THROW(culling::Bvh(boxes, 0), InputError);
}

// A landscape's upper levels are split by binned SAH (more than kBinnedSahAbove objects): on a
// 256 × 256 grid of unit boxes (65 536 trees on flat ground) every object is in one leaf, the nodes
// in preorder with their parents right, every child inside its parent, and the SAH cost is within
// 5% of the balanced tree's that halves the grid's longer side at each level (the test's own
// reference: on a uniform grid that split is the SAH optimum up to rounding).
TEST(Bvh, BinnedSplitsOfALargeGridMatchTheBalancedTree) {
  constexpr int kSide = 256;
  static_assert(kSide * kSide > static_cast<int>(culling::kBinnedSahAbove));
  // In a scrambled order (cell i · 40503 mod 2^16: an odd multiplier permutes), so that the objects'
  // order says nothing about where they are.
  std::vector<Aabb> boxes;
  for (std::uint32_t i = 0; i < kSide * kSide; ++i) {
    const std::uint32_t cell = (i * 40503u) % (kSide * kSide);
    const double x = cell % kSide, z = cell / kSide;
    boxes.push_back({dvec3(x * 3.0, 0.0, z * 3.0), dvec3(x * 3.0 + 1.0, 10.0, z * 3.0 + 1.0)});
  }
  const culling::Bvh bvh(boxes, 1);
  std::vector<int> seen(boxes.size(), 0);
  // The nodes in preorder, each child's parent its own (the upper levels' halves are built on
  // threads of their own and spliced in: the array a serial build makes).
  ASSERT_EQ(bvh.nodes()[0].parent, -1);
  for (const culling::BvhNode& n : bvh.nodes()) {
    if (!n.leaf()) {
      const std::int32_t index = static_cast<std::int32_t>(&n - bvh.nodes().data());
      ASSERT_EQ(n.left, index + 1);
      ASSERT_GT(n.right, n.left);
      for (std::int32_t child : {n.left, n.right}) {
        ASSERT_EQ(bvh.nodes()[child].parent, index);
        ASSERT_TRUE(n.bounds.contains(bvh.nodes()[child].bounds.min) && n.bounds.contains(bvh.nodes()[child].bounds.max));
      }
      continue;
    }
    ASSERT_EQ(n.count, 1u);
    ++seen[bvh.objects()[n.first]];
  }
  for (int s : seen) ASSERT_EQ(s, 1);
  // The balanced reference: Σ over nodes of area(node) / area(root) × (1, or the count at a leaf).
  const std::function<double(int, int, int, int)> balanced = [&](int x0, int z0, int nx, int nz) -> double {
    const Aabb box{dvec3(x0 * 3.0, 0.0, z0 * 3.0), dvec3((x0 + nx - 1) * 3.0 + 1.0, 10.0, (z0 + nz - 1) * 3.0 + 1.0)};
    const double area = culling::surfaceArea(box);
    if (nx * nz == 1) return area;
    if (nx >= nz) return area + balanced(x0, z0, nx / 2, nz) + balanced(x0 + nx / 2, z0, nx - nx / 2, nz);
    return area + balanced(x0, z0, nx, nz / 2) + balanced(x0, z0 + nz / 2, nx, nz - nz / 2);
  };
  const double reference = balanced(0, 0, kSide, kSide) / culling::surfaceArea(bvh.nodes()[0].bounds);
  EXPECT_LE(bvh.sahCost(), 1.05 * reference);
  std::printf("[bvh] binned SAH cost %.1f, balanced tree's %.1f\n", bvh.sahCost(), reference);
}

}  // namespace
}  // namespace forest
