// culling::ReprojectedImage: which objects that showed in the last image its samples, moved into
// the next view, guess hidden. Expected values come from the scenes' construction: each sample is
// placed on the next camera's ray through a chosen point of its image (u, v ∈ [−1, 1]) at a chosen
// eye depth, so where it lands and what lies in front of it are known without the class's
// projection.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "forest/core/camera.hpp"
#include "forest/core/error.hpp"
#include "forest/culling/reprojected_image.hpp"

namespace forest::culling {
namespace {

constexpr int kGrid = 40;  // cells a side

Camera nextCamera() {
  Camera c;
  c.position = {3.0, 2.0, -1.0};
  c.orient(glm::normalize(glm::dvec3(0.3, -0.1, -1.0)), {0.0, 1.0, 0.0});
  c.fovy = glm::radians(60.0);
  c.aspect = 1.0;
  c.near = 0.1;
  c.far = 500.0;
  return c;
}

// The point at eye depth `depth` on the next camera's ray through image point (u, v).
glm::vec3 at(const Camera& c, double u, double v, double depth) {
  const double tanY = std::tan(0.5 * c.fovy), tanX = tanY * c.aspect;
  return glm::vec3(c.position + depth * (c.forward() + u * tanX * c.right() + v * tanY * c.up()));
}

// The image coordinate of cell i's centre.
double centre(int i) { return (2.0 * (i + 0.5)) / kGrid - 1.0; }

// A surface of `object` at `depth` over cells [x0, x1) × [y0, y1), one sample per cell centre
// every `step` cells.
void surface(std::vector<ImageSample>& samples, const Camera& c, std::uint32_t object, double depth, int x0, int x1, int y0, int y1,
             int step = 1) {
  for (int y = y0; y < y1; y += step)
    for (int x = x0; x < x1; x += step) samples.push_back({at(c, centre(x), centre(y), depth), object});
}

std::vector<std::uint8_t> guess(const std::vector<ImageSample>& samples, std::vector<std::uint8_t> shown, std::size_t firstCandidate = 0,
                                int* cleared = nullptr) {
  ReprojectedImage image;
  image.begin(nextCamera(), kGrid, kGrid, shown, firstCandidate);
  image.splat(samples);
  const int n = image.clearHidden(shown);
  if (cleared) *cleared = n;
  return shown;
}

TEST(ReprojectedImage, AnObjectWhollyBehindANearerOneIsGuessedHidden) {
  // Object 0: a wall at 10 m over cells 5–34; object 1: a patch at 30 m over cells 12–19, behind it;
  // object 2: a patch at 30 m over cells 36–38, beside the wall (nothing in front of it).
  const Camera c = nextCamera();
  std::vector<ImageSample> samples;
  surface(samples, c, 1, 30.0, 12, 20, 12, 20);
  surface(samples, c, 0, 10.0, 5, 35, 5, 35);
  surface(samples, c, 2, 30.0, 36, 39, 12, 20);
  int cleared = -1;
  const auto shown = guess(samples, {1, 1, 1}, 0, &cleared);
  EXPECT_EQ(shown, (std::vector<std::uint8_t>{1, 0, 1}));
  EXPECT_EQ(cleared, 1);
}

TEST(ReprojectedImage, OneCellOfAnObjectBesideTheNearerOneShows) {
  // The patch behind reaches one column past the wall's edge (cell 35): it shows there.
  const Camera c = nextCamera();
  std::vector<ImageSample> samples;
  surface(samples, c, 0, 10.0, 5, 35, 5, 35);
  surface(samples, c, 1, 30.0, 28, 36, 12, 20);
  EXPECT_EQ(guess(samples, {1, 1}), (std::vector<std::uint8_t>{1, 1}));
}

TEST(ReprojectedImage, WhatShowsThroughTheHolesOfOneSpreadSurfaceIsHidden) {
  // The wall's samples every other cell (it came nearer): the cells between hold only samples of
  // the patch behind, each with wall samples on both sides of it. Between two walls of different
  // objects one cell apart, the patch shows through the gap.
  const Camera c = nextCamera();
  std::vector<ImageSample> spread;
  surface(spread, c, 0, 10.0, 4, 36, 4, 36, 2);
  surface(spread, c, 1, 30.0, 12, 20, 12, 20);
  EXPECT_EQ(guess(spread, {1, 1}), (std::vector<std::uint8_t>{1, 0}));

  std::vector<ImageSample> gap;
  surface(gap, c, 0, 10.0, 4, 16, 4, 36);   // columns 4–15
  surface(gap, c, 2, 10.0, 17, 36, 4, 36);  // columns 17–35: column 16 open
  surface(gap, c, 1, 30.0, 16, 17, 12, 20);
  EXPECT_EQ(guess(gap, {1, 1, 1}), (std::vector<std::uint8_t>{1, 1, 1}));
}

TEST(ReprojectedImage, OnlyCandidatesAreCleared) {
  // The patch behind is object 1: below firstCandidate = 2, or not flagged, it keeps its flag.
  const Camera c = nextCamera();
  std::vector<ImageSample> samples;
  surface(samples, c, 0, 10.0, 5, 35, 5, 35);
  surface(samples, c, 1, 30.0, 12, 20, 12, 20);
  EXPECT_EQ(guess(samples, {1, 1}, 2), (std::vector<std::uint8_t>{1, 1}));
  EXPECT_EQ(guess(samples, {1, 0}), (std::vector<std::uint8_t>{1, 0}));
}

TEST(ReprojectedImage, DegenerateSamples) {
  const Camera c = nextCamera();
  std::vector<ImageSample> samples;
  // Object 0: behind the next eye; object 1: off the image (u = 1.5): samples that do not show.
  // Object 2: its only sample not finite, object 3: no sample at all: nothing known, flags kept.
  // Object 4: just beyond the near plane, nothing in front: shows.
  samples.push_back({at(c, 0.0, 0.0, -5.0), 0});
  samples.push_back({at(c, 1.5, 0.0, 20.0), 1});
  samples.push_back({glm::vec3(std::numeric_limits<float>::quiet_NaN(), 0.0f, 0.0f), 2});
  samples.push_back({at(c, 0.0, 0.0, c.near * 1.01), 4});
  // Samples of objects beyond the flags are ignored, even nearer ones in the same cell.
  samples.push_back({at(c, 0.0, 0.0, c.near * 1.005), 9});
  int cleared = -1;
  EXPECT_EQ(guess(samples, {1, 1, 1, 1, 1}, 0, &cleared), (std::vector<std::uint8_t>{0, 0, 1, 1, 1}));
  EXPECT_EQ(cleared, 2);
  ReprojectedImage image;
  const std::vector<std::uint8_t> none;
  EXPECT_THROW(image.begin(c, 0, kGrid, none, 0), Error);
}

}  // namespace
}  // namespace forest::culling
