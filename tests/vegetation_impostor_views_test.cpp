// The impostors' bake views (vegetation/impostor_views.hpp): the hemi-octahedral map and its
// inverse, the views' frames, and which view a direction falls to — against their closed forms.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "forest/vegetation/impostor_views.hpp"

namespace forest::vegetation {
namespace {

using glm::dvec2;
using glm::dvec3;

// A direction uniformly over the upper hemisphere (y ≥ 0).
dvec3 upperDirection(std::mt19937_64& random) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double y = unit(random), phi = 2.0 * std::numbers::pi * unit(random), r = std::sqrt(1.0 - y * y);
  return {r * std::cos(phi), y, r * std::sin(phi)};
}

TEST(ImpostorViews, TheHemiOctahedralMapIsItsInversesInverse) {
  // Closed forms: the zenith is the square's centre, the horizon its border (|u| or |v| = 1).
  EXPECT_NEAR(glm::length(hemiOctahedral(dvec3(0.0, 1.0, 0.0))), 0.0, 1e-15);
  EXPECT_NEAR(hemiOctahedral(dvec3(1.0, 0.0, 0.0)).x, 1.0, 1e-15);
  EXPECT_NEAR(hemiOctahedral(dvec3(1.0, 0.0, 0.0)).y, 1.0, 1e-15);
  EXPECT_NEAR(hemiOctahedral(dvec3(0.0, 0.0, -1.0)).x, -1.0, 1e-15);
  EXPECT_NEAR(hemiOctahedral(dvec3(0.0, 0.0, -1.0)).y, 1.0, 1e-15);
  std::mt19937_64 random(7);
  for (int k = 0; k < 10000; ++k) {
    const dvec3 d = upperDirection(random);
    const dvec2 s = hemiOctahedral(d);
    ASSERT_LE(std::abs(s.x), 1.0 + 1e-12);
    ASSERT_LE(std::abs(s.y), 1.0 + 1e-12);
    const dvec3 back = fromHemiOctahedral(s);
    ASSERT_NEAR(glm::distance(back, d), 0.0, 1e-12) << "direction " << d.x << " " << d.y << " " << d.z;
  }
  // Below the horizon folds onto it.
  const dvec3 below = fromHemiOctahedral(hemiOctahedral(glm::normalize(dvec3(1.0, -0.5, 1.0))));
  EXPECT_NEAR(glm::distance(below, glm::normalize(dvec3(1.0, 0.0, 1.0))), 0.0, 1e-12);
}

TEST(ImpostorViews, EachViewIsARightHandedFrameWithAHorizontalRight) {
  const ImpostorGrid grid(16);
  for (int i = 0; i < grid.views(); ++i)
    for (int j = 0; j < grid.views(); ++j) {
      const ImpostorFrame f = grid.frame(i, j);
      EXPECT_NEAR(glm::length(f.toViewer), 1.0, 1e-12);
      EXPECT_NEAR(glm::length(f.right), 1.0, 1e-12);
      EXPECT_NEAR(glm::length(f.up), 1.0, 1e-12);
      EXPECT_NEAR(glm::dot(f.right, f.up), 0.0, 1e-12);
      EXPECT_NEAR(glm::distance(glm::cross(f.right, f.up), f.toViewer), 0.0, 1e-12);
      EXPECT_NEAR(f.right.y, 0.0, 1e-12);
      EXPECT_GE(f.up.y, 0.0);  // the image's up is the world's up, tilted
      EXPECT_GE(f.toViewer.y, 0.0);
      EXPECT_EQ(grid.cellOf(f.toViewer), glm::ivec2(i, j));
    }
  // The one view the grid has looks from the zenith, which has no horizontal right: +x.
  const ImpostorFrame top = ImpostorGrid(1).frame(0, 0);
  EXPECT_NEAR(glm::distance(top.toViewer, dvec3(0.0, 1.0, 0.0)), 0.0, 1e-12);
  EXPECT_NEAR(glm::distance(top.right, dvec3(1.0, 0.0, 0.0)), 0.0, 1e-12);
}

// A direction falls to the view whose cell holds it, so it is no farther from that view than the
// cell's farthest corner: ImpostorGrid::largestAngle bounds it — checked on 20 000 random directions.
TEST(ImpostorViews, ADirectionTakesTheViewOfTheCellThatHoldsIt) {
  const int views = 16;
  const ImpostorGrid grid(views);
  const double bound = grid.largestAngle();
  EXPECT_LT(bound, 9.0 * std::numbers::pi / 180.0);  // a 16-view grid: under 9° from any direction to its view
  std::mt19937_64 random(11);
  for (int k = 0; k < 20000; ++k) {
    const dvec3 d = upperDirection(random);
    const glm::ivec2 cell = grid.cellOf(d);
    const dvec2 s = hemiOctahedral(d);
    // The cell holds the direction's point of the square.
    ASSERT_GE(s.x, 2.0 * cell.x / views - 1.0 - 1e-12);
    ASSERT_LE(s.x, 2.0 * (cell.x + 1) / views - 1.0 + 1e-12);
    ASSERT_GE(s.y, 2.0 * cell.y / views - 1.0 - 1e-12);
    ASSERT_LE(s.y, 2.0 * (cell.y + 1) / views - 1.0 + 1e-12);
    ASSERT_LE(std::acos(std::min(1.0, glm::dot(d, grid.frame(cell.x, cell.y).toViewer))), bound + 1e-12);
  }
}

}  // namespace
}  // namespace forest::vegetation
