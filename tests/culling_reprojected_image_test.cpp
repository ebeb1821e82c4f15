// culling::ReprojectedImage: which objects that showed in the last image its samples, moved into
// the next view, guess hidden. Expected values come from the scenes' construction: the last image
// is painted sample by sample (an object at an eye depth over a rectangle of samples), the next
// camera is the last one moved along one of its axes, and where a sample lands follows in closed
// form (below), without the class's projection.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "forest/core/camera.hpp"
#include "forest/core/error.hpp"
#include "forest/culling/reprojected_image.hpp"

namespace forest::culling {
namespace {

constexpr int kGrid = 40;  // samples, and cells, a side: an image of 80 × 80 pixels

// fovy 90°, aspect 1: a sample's ray is forward + v · up + u · right with u, v its normalised
// device coordinates, so that cell i of the next view holds u ∈ [i / 20 − 1, (i + 1) / 20 − 1).
// Sample i of the last image sits at u = (i + ¼) / 20 − 1 (the centre of its first pixel).
// Moved right by t, a point at eye depth z keeps z and moves by −20 t / z cells; moved forward by
// t, it comes to depth z − t and its u to u · z / (z − t).
Camera lastCamera() {
  Camera c;
  c.position = {3.0, 2.0, -1.0};
  c.orient(glm::normalize(glm::dvec3(0.3, -0.1, -1.0)), {0.0, 1.0, 0.0});
  c.fovy = glm::radians(90.0);
  c.aspect = 1.0;
  c.near = 0.1;
  c.far = 500.0;
  return c;
}

Camera moved(const Camera& c, double right, double forward) {
  Camera m = c;
  m.position += right * c.right() + forward * c.forward();
  return m;
}

SampledImage emptyImage(const Camera& last) {
  SampledImage image;
  image.reset(last, 2 * kGrid, 2 * kGrid);
  return image;
}

// Object `object` at eye depth `depth` over samples [x0, x1) × [y0, y1).
void paint(SampledImage& image, std::uint32_t object, float depth, int x0, int x1, int y0, int y1) {
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) {
      image.depths[static_cast<size_t>(y * kGrid + x)] = depth;
      image.objects[static_cast<size_t>(y * kGrid + x)] = object + 1u;
    }
}

// Object 0: a wall at 10 m over samples 5–19 (rows 5–34); object 1: a patch at 30 m over samples
// [20, patchEnd) (rows 12–19), beside it. The eye moving 3 m left takes the wall 6 cells right
// (cells 11–25) and the patch 2 (cells 22 to patchEnd + 1).
SampledImage wallBesidePatch(const Camera& last, int patchEnd) {
  SampledImage image = emptyImage(last);
  paint(image, 0, 10.0f, 5, 20, 5, 35);
  paint(image, 1, 30.0f, 20, patchEnd, 12, 20);
  return image;
}

std::vector<std::uint8_t> guess(const SampledImage& image, const Camera& next, std::vector<std::uint8_t> shown,
                                std::size_t firstCandidate = 0, int* cleared = nullptr) {
  ReprojectedImage reprojected;
  reprojected.begin(next, kGrid, kGrid, shown, firstCandidate);
  reprojected.splat(image);
  const int n = reprojected.clearHidden(shown);
  if (cleared) *cleared = n;
  return shown;
}

TEST(ReprojectedImage, SampleRaysArePixelCentresOfTheCamera) {
  // reset: the rays the frame's ReceiverPixels give, every kSampleStride-th pixel centre.
  const Camera c = lastCamera();
  const SampledImage image = emptyImage(c);
  ASSERT_EQ(image.columns.size(), static_cast<size_t>(kGrid));
  ASSERT_EQ(image.rows.size(), static_cast<size_t>(kGrid));
  for (int i = 0; i < kGrid; ++i) {
    EXPECT_NEAR(image.columns[static_cast<size_t>(i)], (i + 0.25) / 20.0 - 1.0, 1e-12);
    EXPECT_NEAR(image.rows[static_cast<size_t>(i)], (i + 0.25) / 20.0 - 1.0, 1e-12);
  }
  EXPECT_NEAR(glm::distance(image.forward, c.forward()), 0.0, 1e-12);
  EXPECT_NEAR(glm::distance(image.right, c.right()), 0.0, 1e-12);
  EXPECT_NEAR(glm::distance(image.up, c.up()), 0.0, 1e-12);
  EXPECT_EQ(image.objects, std::vector<std::uint32_t>(kGrid * kGrid, 0u));
}

TEST(ReprojectedImage, AnObjectANearerOneMovesInFrontOfIsGuessedHidden) {
  // The patch over samples 20–23 lands under the wall (cells 22–25); object 2, a patch at 30 m
  // over samples 30–33, lands on 32–35 with nothing in front.
  const Camera last = lastCamera();
  SampledImage image = wallBesidePatch(last, 24);
  paint(image, 2, 30.0f, 30, 34, 12, 20);
  int cleared = -1;
  EXPECT_EQ(guess(image, moved(last, -3.0, 0.0), {1, 1, 1}, 0, &cleared), (std::vector<std::uint8_t>{1, 0, 1}));
  EXPECT_EQ(cleared, 1);
  // Without the move nothing is in front of anything: all show.
  EXPECT_EQ(guess(image, last, {1, 1, 1}), (std::vector<std::uint8_t>{1, 1, 1}));
}

TEST(ReprojectedImage, OneCellOfAnObjectBesideTheNearerOneShows) {
  // The patch over samples 20–26 lands on cells 22–28: 26–28 lie past the wall's last cell, 25.
  const Camera last = lastCamera();
  const SampledImage image = wallBesidePatch(last, 27);
  EXPECT_EQ(guess(image, moved(last, -3.0, 0.0), {1, 1}), (std::vector<std::uint8_t>{1, 1}));
}

TEST(ReprojectedImage, WhatShowsThroughTheHolesOfOneSpreadSurfaceIsHidden) {
  // The eye moves 5 m forward: the wall at 10 m over samples 8–31 spreads by 10 / 5 = 2 (sample i
  // to cell 2 i − 19.5: every other cell, all over the image), the patch at 30 m beside it (samples
  // 32–33, rows 16–23) by 30 / 25 = 1.2 (to cells 34–35, rows 15–19). Each of its cells is one of
  // the wall's or lies between two of them: it is hidden.
  const Camera last = lastCamera();
  SampledImage spread = emptyImage(last);
  paint(spread, 0, 10.0f, 8, 32, 8, 32);
  paint(spread, 1, 30.0f, 32, 34, 16, 24);
  EXPECT_EQ(guess(spread, moved(last, 0.0, 5.0), {1, 1}), (std::vector<std::uint8_t>{1, 0}));

  // Between two walls of different objects one cell apart (no move), the patch shows through the gap.
  SampledImage gap = emptyImage(last);
  paint(gap, 0, 10.0f, 4, 16, 4, 36);   // columns 4–15
  paint(gap, 2, 10.0f, 17, 36, 4, 36);  // columns 17–35: column 16 open
  paint(gap, 1, 30.0f, 16, 17, 12, 20);
  EXPECT_EQ(guess(gap, last, {1, 1, 1}), (std::vector<std::uint8_t>{1, 1, 1}));
}

TEST(ReprojectedImage, OnlyCandidatesAreCleared) {
  // The patch under the wall is object 1: below firstCandidate = 2, or not flagged, it keeps its flag.
  const Camera last = lastCamera();
  const SampledImage image = wallBesidePatch(last, 24);
  EXPECT_EQ(guess(image, moved(last, -3.0, 0.0), {1, 1}, 2), (std::vector<std::uint8_t>{1, 1}));
  EXPECT_EQ(guess(image, moved(last, -3.0, 0.0), {1, 0}), (std::vector<std::uint8_t>{1, 0}));
}

TEST(ReprojectedImage, DegenerateSamples) {
  // A 7 × 1 image of chosen rays; the eye moves 10 m forward.
  const Camera last = lastCamera();
  SampledImage image;
  image.eye = last.position;
  image.forward = last.forward();
  image.up = last.up();
  image.right = last.right();
  image.rows = {0.0};
  image.columns = {0.0, 0.9625, 0.0, 0.0, 0.0, 0.0, 0.0};
  // Object 0 at 5 m: behind the next eye. Object 1 at 20 m, u = 0.9625: at u = 1.925, off the
  // image. Neither shows. Object 2: depth NaN; object 3: depth −1; object 5: no sample at all:
  // nothing known, flags kept. Object 4 at 10.101 m: 1.01 near distances beyond the next eye,
  // nothing in front: shows. Object 6 at 10.05 m in the same cell, in front of the next eye but
  // short of its near plane: does not show (nor hide object 4). Object 9 at 10.1005 m, nearer in
  // the same cell than object 4, is beyond the flags: ignored.
  image.depths = {5.0f, 20.0f, std::numeric_limits<float>::quiet_NaN(), -1.0f, 10.101f, 10.05f, 10.1005f};
  image.objects = {1, 2, 3, 4, 5, 7, 10};
  int cleared = -1;
  EXPECT_EQ(guess(image, moved(last, 0.0, 10.0), {1, 1, 1, 1, 1, 1, 1}, 0, &cleared),
            (std::vector<std::uint8_t>{0, 0, 1, 1, 1, 1, 0}));
  EXPECT_EQ(cleared, 3);

  ReprojectedImage reprojected;
  const std::vector<std::uint8_t> none;
  EXPECT_THROW(reprojected.begin(last, 0, kGrid, none, 0), Error);
  reprojected.begin(last, kGrid, kGrid, none, 0);
  image.objects.pop_back();  // fewer objects than depths
  EXPECT_THROW(reprojected.splat(image), Error);
  SampledImage noPixels;
  EXPECT_THROW(noPixels.reset(last, 0, 4), Error);
}

}  // namespace
}  // namespace forest::culling
