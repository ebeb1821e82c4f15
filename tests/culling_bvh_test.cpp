// The culling BVH (culling/bvh.hpp), without GL: every object in exactly one leaf whose box holds
// it, every child inside its parent, after a build and after refits of moved boxes.
#include <gtest/gtest.h>
#include <glm/glm.hpp>

#include <cmath>
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

}  // namespace
}  // namespace forest
