// MaxPyramid against a brute-force maximum over every rectangle of random grids (odd sizes
// included): never below the true maximum, never above the maximum over the blocks that hold the
// rectangle at the level it is answered from (each block at most twice the rectangle's larger side).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "forest/core/error.hpp"
#include "forest/core/max_pyramid.hpp"

namespace forest {
namespace {

float bruteMax(const std::vector<float>& v, int width, int x0, int y0, int x1, int y1) {
  float m = -std::numeric_limits<float>::infinity();
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) m = std::max(m, v[static_cast<size_t>(y * width + x)]);
  return m;
}

TEST(MaxPyramid, NeverBelowTheRectanglesMaximumNorAboveItsBlocks) {
  std::mt19937 random(7);
  for (const auto& [width, height] : {std::pair{1, 1}, std::pair{1, 9}, std::pair{13, 1}, std::pair{16, 16}, std::pair{37, 23}}) {
    std::vector<float> values(static_cast<size_t>(width * height));
    std::uniform_real_distribution<float> uniform(-1.0f, 1.0f);
    for (float& v : values) v = uniform(random);
    MaxPyramid pyramid;
    pyramid.build(values, width, height);
    EXPECT_EQ(pyramid.levels(), 1 + static_cast<int>(std::ceil(std::log2(std::max(width, height)))));
    int exact = 0, rectangles = 0;
    for (int y0 = 0; y0 < height; ++y0)
      for (int y1 = y0; y1 < height; ++y1)
        for (int x0 = 0; x0 < width; ++x0)
          for (int x1 = x0; x1 < width; ++x1) {
            const float got = pyramid.maxOver(x0, y0, x1, y1), truth = bruteMax(values, width, x0, y0, x1, y1);
            ASSERT_GE(got, truth) << width << "x" << height << " [" << x0 << ", " << x1 << "] x [" << y0 << ", " << y1 << "]";
            // The blocks of the finest level where the range spans at most two each way.
            int k = 0;
            while ((x1 >> k) - (x0 >> k) > 1 || (y1 >> k) - (y0 >> k) > 1) ++k;
            const int bx0 = (x0 >> k) << k, by0 = (y0 >> k) << k;
            const int bx1 = std::min(width - 1, (((x1 >> k) + 1) << k) - 1), by1 = std::min(height - 1, (((y1 >> k) + 1) << k) - 1);
            ASSERT_LE(got, bruteMax(values, width, bx0, by0, bx1, by1));
            exact += got == truth;
            ++rectangles;
          }
    // Single texels and 2 × 2-aligned pairs are answered from level 0: exactly.
    EXPECT_EQ(pyramid.maxOver(width - 1, height - 1, width - 1, height - 1), values.back());
    EXPECT_GT(exact, 0);
    EXPECT_GT(rectangles, 0);
  }
}

TEST(MaxPyramid, ClampsToTheGridAndAnswersMinusInfinityForAnEmptyRange) {
  const std::vector<float> values{1.0f, 5.0f, 3.0f, 2.0f};
  MaxPyramid pyramid;
  pyramid.build(values, 2, 2);
  EXPECT_EQ(pyramid.maxOver(-10, -10, 10, 10), 5.0f);
  EXPECT_EQ(pyramid.maxOver(0, 1, 0, 1), 3.0f);
  EXPECT_EQ(pyramid.maxOver(1, 0, 0, 0), -std::numeric_limits<float>::infinity());
  EXPECT_EQ(pyramid.maxOver(5, 5, 9, 9), -std::numeric_limits<float>::infinity());
  EXPECT_THROW(pyramid.build(values, 3, 2), Error);
}

}  // namespace
}  // namespace forest
