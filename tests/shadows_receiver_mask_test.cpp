// The receiver mask (shadows::ReceiverMask, Bittner et al. 2011 §4) on a map whose geometry is a
// closed form: the sun straight down, map x = world x / 50, map y = world z / 50, depth = −y / 100
// (higher is nearer the light), 1024² texels over 100 m (0.098 m per texel), 256² cells.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <span>
#include <vector>

#include "forest/core/error.hpp"
#include "forest/shadows/receiver_mask.hpp"

namespace forest::shadows {
namespace {

using glm::dvec3;

ShadowSetup overheadSetup() {
  ShadowSetup s;
  s.worldToShadowClip = glm::dmat4(0.0);
  s.worldToShadowClip[0][0] = 1.0 / 50.0;   // x → map x
  s.worldToShadowClip[2][1] = 1.0 / 50.0;   // z → map y
  s.worldToShadowClip[1][2] = -1.0 / 100.0; // y → depth
  s.worldToShadowClip[3][3] = 1.0;
  s.empty = false;
  return s;
}

TEST(ReceiverMask, ACasterShadowsOnlyReceiversBelowItWithinTheFiltersReach) {
  ReceiverMask mask;
  mask.reset(overheadSetup(), 1024, 256);
  EXPECT_FALSE(mask.mayShadow(Aabb{dvec3(-1, 5, -1), dvec3(1, 6, 1)}, 1.0));  // no receivers yet
  mask.add(dvec3(0.1, 0.0, 0.1));
  EXPECT_EQ(mask.receivers(), 1);
  EXPECT_TRUE(mask.mayShadow(Aabb{dvec3(-1, 5, -1), dvec3(1, 6, 1)}, 1.0));     // above it
  EXPECT_FALSE(mask.mayShadow(Aabb{dvec3(-1, -6, -1), dvec3(1, -5, 1)}, 1.0));  // below it: farther from the light
  EXPECT_FALSE(mask.mayShadow(Aabb{dvec3(10, 5, -1), dvec3(12, 6, 1)}, 1.0));   // beside it
  // A caster whose near edge is 3 m (30.7 texels) beside the receiver's cell [0, 0.39 m): a reach of
  // 40 texels (3.9 m) covers the cell, a reach of 20 (1.95 m) stops 1.05 m short of it, more than
  // the cell's 0.39 m.
  const Aabb beside{dvec3(0.39 + 3.0, 5, -1), dvec3(0.39 + 4.0, 6, 1)};
  EXPECT_TRUE(mask.mayShadow(beside, 40.0));
  EXPECT_FALSE(mask.mayShadow(beside, 20.0));
}

// The cell keeps the receiver farthest from the light: a caster between two receivers of one
// cell (one above it, one below) may shadow the lower one.
TEST(ReceiverMask, ACellKeepsItsFarthestReceiver) {
  ReceiverMask mask;
  mask.reset(overheadSetup(), 1024, 256);
  mask.add(dvec3(0.1, 10.0, 0.1));
  const Aabb between{dvec3(0.0, 4.0, 0.0), dvec3(0.2, 5.0, 0.2)};
  EXPECT_FALSE(mask.mayShadow(between, 0.5));  // only a receiver above it so far
  mask.add(dvec3(0.15, 0.0, 0.15));
  EXPECT_TRUE(mask.mayShadow(between, 0.5));
}

// Receivers outside the map read its border texels (clamped), and count in the border cells.
TEST(ReceiverMask, ReceiversOutsideTheMapCountAtItsBorder) {
  ReceiverMask mask;
  mask.reset(overheadSetup(), 1024, 256);
  mask.add(dvec3(70.0, 0.0, 0.0));  // map x = 1.4
  EXPECT_TRUE(mask.mayShadow(Aabb{dvec3(49.9, 5, -0.1), dvec3(60, 6, 0.1)}, 0.5));
  EXPECT_FALSE(mask.mayShadow(Aabb{dvec3(40, 5, -0.1), dvec3(45, 6, 0.1)}, 0.5));
  EXPECT_THROW(mask.reset(overheadSetup(), 1024, 0), Error);
}

// A receiver behind the light's projection (w ≤ 0) cannot be placed in the map: every caster is kept.
TEST(ReceiverMask, AReceiverTheMapCannotPlaceKeepsEveryCaster) {
  ShadowSetup s = overheadSetup();
  s.worldToShadowClip[1][3] = 1.0;  // w = 1 + y: y ≤ −1 lies behind the projection
  ReceiverMask mask;
  mask.reset(s, 1024, 256);
  mask.add(dvec3(0.0, -2.0, 0.0));
  const Aabb farCaster{dvec3(30, 5, 30), dvec3(31, 6, 31)};
  EXPECT_TRUE(mask.mayShadow(farCaster, 0.5));

  // The same point as a pixel of an eye row (an eye at the origin looking down: depth 2 m), with
  // pixels that are no receivers beside it: a NaN depth and one beyond zMax. Without the point
  // the row leaves the mask empty; with it, every caster may shadow.
  EyeRays down;
  down.eye = dvec3(0.0);
  down.forward = dvec3(0.0, -1.0, 0.0);
  down.right = dvec3(1.0, 0.0, 0.0);
  down.up = dvec3(0.0, 0.0, -1.0);
  const std::vector<float> columns{0.0f, 0.0f, 0.0f};
  const float nan = std::numeric_limits<float>::quiet_NaN();
  ReceiverMask byRow;
  byRow.reset(s, 1024, 256);
  byRow.addEyeRow(down, 0.0f, columns, std::vector<float>{nan, 50.0f, 0.0f}, 0.5, 40.0);
  EXPECT_EQ(byRow.receivers(), 0);
  EXPECT_FALSE(byRow.mayShadow(farCaster, 0.5));
  byRow.addEyeRow(down, 0.0f, columns, std::vector<float>{nan, 50.0f, 2.0f}, 0.5, 40.0);
  EXPECT_TRUE(byRow.mayShadow(farCaster, 0.5));
}

// Pixels handed over row by row as eye rays (addEyeRow, a frame's path) fill the mask as the same
// points given as world positions (add): every probe caster gets the same answer. A map with a
// perspective (w varies with height, so the division matters), with map depth as clip z / w and as
// tsm's linear light depth; an eye looking down and across the map, and only the depths inside
// [zMin, zMax] counted. Two images: 80 × 50 pixels at scattered depths of 0.5–60 m, some without a
// receiver (depth 0), so that neighbours rarely share a cell; and 400 × 50 pixels of a rippled
// ground plane (every other pixel 1% nearer; sky above the horizon), so that runs of neighbours share
// one and the nearest of a run is often its last (addEyeRow keeps a run's cell in a register).
TEST(ReceiverMask, EyeRowsFillTheMaskAsTheirWorldPositionsDo) {
  ShadowSetup perspective = overheadSetup();
  perspective.worldToShadowClip[1][3] = 0.02;  // w = 1 + y / 50
  ShadowSetup linear = perspective;
  linear.linearDepth = true;
  linear.worldToLightDepth = glm::dvec4(0.0, -1.0 / 80.0, 0.0, 0.1);
  const double yaw = 0.7, pitch = -0.4;
  EyeRays rays;
  rays.eye = dvec3(-3.0, 12.0, 5.0);
  rays.forward = dvec3(std::cos(pitch) * std::sin(yaw), std::sin(pitch), -std::cos(pitch) * std::cos(yaw));
  rays.right = glm::normalize(glm::cross(rays.forward, dvec3(0.0, 1.0, 0.0)));
  rays.up = glm::cross(rays.right, rays.forward);
  std::mt19937_64 random(11);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), depth(0.5, 60.0);
  const double zMin = 2.0, zMax = 40.0;
  auto check = [&](const char* image, int width, int height, const std::function<float(int, double, double)>& depthAt) {
    std::vector<float> columns(width), rows(height), depths(static_cast<size_t>(width) * height);
    for (int x = 0; x < width; ++x) columns[static_cast<size_t>(x)] = static_cast<float>(0.8 * (2.0 * (x + 0.5) / width - 1.0));
    for (int y = 0; y < height; ++y) rows[static_cast<size_t>(y)] = static_cast<float>(0.6 * (2.0 * (y + 0.5) / height - 1.0));
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x)
        depths[static_cast<size_t>(y) * width + x] = depthAt(x, columns[static_cast<size_t>(x)], rows[static_cast<size_t>(y)]);
    for (const ShadowSetup& setup : {perspective, linear}) {
      ReceiverMask byWorld, byRays;
      byWorld.reset(setup, 1024, 256);
      byRays.reset(setup, 1024, 256);
      for (int y = 0; y < height; ++y) {
        const std::span<const float> row(depths.data() + static_cast<size_t>(y) * width, width);
        for (int x = 0; x < width; ++x) {
          const double z = row[static_cast<size_t>(x)], cx = columns[static_cast<size_t>(x)], cy = rows[static_cast<size_t>(y)];
          if (z >= zMin && z <= zMax) byWorld.add(rays.eye + z * (rays.forward + cx * rays.right + cy * rays.up));
        }
        byRays.addEyeRow(rays, rows[static_cast<size_t>(y)], columns, row, zMin, zMax);
      }
      ASSERT_EQ(byRays.receivers(), byWorld.receivers()) << image;
      ASSERT_GT(byWorld.receivers(), 1000) << image;
      int shadowing = 0, differing = 0;
      for (int i = 0; i < 3000; ++i) {
        const dvec3 corner(30.0 * unit(random), 2.0 + 8.0 * unit(random), 30.0 * unit(random));
        const Aabb caster{corner, corner + dvec3(0.6, 1.0, 0.6)};
        const bool expected = byWorld.mayShadow(caster, 0.5);
        shadowing += expected ? 1 : 0;
        differing += expected != byRays.mayShadow(caster, 0.5) ? 1 : 0;
      }
      EXPECT_EQ(differing, 0) << image;
      EXPECT_GT(shadowing, 100) << image;       // the probes meet receivers …
      EXPECT_LT(shadowing, 3000 - 100) << image;  // … and miss them
      // And probes just above receivers (2–3 cm, toward the light): a cell that kept a nearer
      // receiver than its farthest would lose some of them.
      int close = 0, closeDiffering = 0;
      for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; x += 3) {
          const double z = depths[static_cast<size_t>(y) * width + x];
          if (!(z >= zMin && z <= zMax)) continue;
          const dvec3 p = rays.eye + z * (rays.forward + double(columns[static_cast<size_t>(x)]) * rays.right +
                                          double(rows[static_cast<size_t>(y)]) * rays.up);
          const Aabb caster{p + dvec3(-0.005, 0.02, -0.005), p + dvec3(0.005, 0.03, 0.005)};
          ++close;
          closeDiffering += byWorld.mayShadow(caster, 0.0) != byRays.mayShadow(caster, 0.0) ? 1 : 0;
        }
      EXPECT_GT(close, 300) << image;
      EXPECT_EQ(closeDiffering, 0) << image;
    }
  };
  check("scattered", 80, 50, [&](int, double, double) { return unit(random) < -0.8 ? 0.0f : static_cast<float>(depth(random)); });
  check("rippled ground", 400, 50, [&](int column, double x, double y) {
    const double down = -(rays.forward + x * rays.right + y * rays.up).y;  // the ray's drop per unit of eye depth
    const double ripple = column % 2 == 1 ? 0.99 : 1.0;
    return down > 0.0 ? static_cast<float>(ripple * rays.eye.y / down) : 0.0f;  // y = 0 at that eye depth; 0: sky
  });
}

// A frame fills one mask per band of pixels, each on a thread of its own, and merges them
// (ShadowSetupPass::fillReceiverMask). The reference is one mask of all the points, added one by
// one: the merged mask must hold the same receivers and give every probe caster the same answer.
// The parts are spatially interleaved (the frame's bands share rows in turn), so that many cells
// take points from both; the point behind the projection in the second part must carry over too.
TEST(ReceiverMask, MasksOfPartsMergeIntoTheMaskOfAllPoints) {
  std::mt19937_64 random(5);
  std::uniform_real_distribution<double> across(-40.0, 40.0), height(0.0, 12.0);
  std::vector<dvec3> points;
  for (int i = 0; i < 6000; ++i) points.push_back({across(random), height(random), across(random)});
  ReceiverMask all, first, second;
  for (ReceiverMask* m : {&all, &first, &second}) m->reset(overheadSetup(), 1024, 256);
  for (size_t i = 0; i < points.size(); ++i) {
    all.add(points[i]);
    (i % 2 == 0 ? first : second).add(points[i]);
  }
  // Merged at once, and in two parts (as the frame's threads do, each a share of the cells).
  ReceiverMask inParts = first;
  first.merge(second);
  inParts.merge(second, 1, 2);
  inParts.merge(second, 0, 2);
  EXPECT_EQ(first.receivers(), all.receivers());
  EXPECT_EQ(inParts.receivers(), all.receivers());
  int shadowing = 0, differing = 0, differingInParts = 0;
  for (int i = 0; i < 3000; ++i) {
    const dvec3 corner(across(random), height(random), across(random));
    const Aabb caster{corner, corner + dvec3(0.3, 0.5, 0.3)};
    const bool expected = all.mayShadow(caster, 0.5);
    shadowing += expected ? 1 : 0;
    differing += expected != first.mayShadow(caster, 0.5) ? 1 : 0;
    differingInParts += expected != inParts.mayShadow(caster, 0.5) ? 1 : 0;
  }
  EXPECT_EQ(differing, 0);
  EXPECT_EQ(differingInParts, 0);
  EXPECT_THROW(inParts.merge(second, 2, 2), Error);
  EXPECT_GT(shadowing, 100);
  EXPECT_LT(shadowing, 3000 - 100);

  // A receiver the map cannot place, in one part only: the merged mask keeps every caster.
  ShadowSetup behind = overheadSetup();
  behind.worldToShadowClip[1][3] = 1.0;  // w = 1 + y
  ReceiverMask placed, unplaced;
  placed.reset(behind, 1024, 256);
  unplaced.reset(behind, 1024, 256);
  placed.add(dvec3(0.0, 0.0, 0.0));
  unplaced.add(dvec3(0.0, -2.0, 0.0));
  placed.merge(unplaced);
  EXPECT_TRUE(placed.mayShadow(Aabb{dvec3(30, 5, 30), dvec3(31, 6, 31)}, 0.5));
  EXPECT_EQ(placed.texelsRead(0.5).texels(), 1024LL * 1024);
  // The texels read of merged parts: those of all their points (one in the south-west, one in the
  // north-east), merged by part 0, which takes the counts.
  ReceiverMask southWest, northEast, both;
  for (ReceiverMask* m : {&southWest, &northEast, &both}) m->reset(overheadSetup(), 1024, 256);
  southWest.add(dvec3(-30.0, 0.0, -20.0));
  northEast.add(dvec3(25.0, 0.0, 35.0));
  both.add(dvec3(-30.0, 0.0, -20.0));
  both.add(dvec3(25.0, 0.0, 35.0));
  southWest.merge(northEast, 1, 2);
  southWest.merge(northEast, 0, 2);
  const TexelRect merged = southWest.texelsRead(1.5), expected = both.texelsRead(1.5);
  EXPECT_EQ(glm::ivec4(merged.x0, merged.y0, merged.x1, merged.y1), glm::ivec4(expected.x0, expected.y0, expected.x1, expected.y1));
  EXPECT_GT(expected.texels(), 500LL * 500);
  // Masks of different maps or cells do not merge.
  ReceiverMask coarse;
  coarse.reset(overheadSetup(), 1024, 128);
  EXPECT_THROW(all.merge(coarse), Error);
}

// Within a cell (4 texels, 0.39 m), only the sub-cells (1 texel) a box's footprint reaches count: a
// box ending at x = 0, with a reach of half a texel (0.049 m), cannot shadow a receiver at
// x = 0.35 m, three sub-cells away in the same cell; one at x = 0.05 m, in the first sub-cell, it may.
TEST(ReceiverMask, OnlyTheSubCellsAFootprintReachesCount) {
  ReceiverMask mask;
  mask.reset(overheadSetup(), 1024, 256);
  const Aabb caster{dvec3(-1.0, 5.0, -0.2), dvec3(0.0, 6.0, 0.2)};
  mask.add(dvec3(0.35, 0.0, 0.1));
  EXPECT_FALSE(mask.mayShadow(caster, 0.5));
  EXPECT_TRUE(mask.mayShadow(caster, 4.0));  // a reach of 4 texels (0.39 m) gets there
  mask.add(dvec3(0.05, 0.0, 0.1));
  EXPECT_TRUE(mask.mayShadow(caster, 0.5));
}

// The box's outline in the map decides, not its bounding rectangle. A map turned 45° to the world
// (map x ∝ x + z, map y ∝ z − x; 0.098 m a texel): the unit box over [0, 1] × [0, 1] shows as a
// diamond. A receiver at (0.5, 1.4) lies inside the diamond's bounding rectangle but 0.4 m (4
// texels) from the diamond: no shadow with a reach of half a texel. One at (0.5, 1.04), 0.04 m
// from the box, may be.
TEST(ReceiverMask, TheBoxsOutlineNotItsRectangleDecides) {
  ShadowSetup turned = overheadSetup();
  const double scale = 1.0 / (50.0 * std::sqrt(2.0));
  turned.worldToShadowClip = glm::dmat4(0.0);
  turned.worldToShadowClip[0][0] = scale;   // x → map x
  turned.worldToShadowClip[2][0] = scale;   // z → map x
  turned.worldToShadowClip[0][1] = -scale;  // x → map y
  turned.worldToShadowClip[2][1] = scale;   // z → map y
  turned.worldToShadowClip[1][2] = -1.0 / 100.0;
  turned.worldToShadowClip[3][3] = 1.0;
  ReceiverMask mask;
  mask.reset(turned, 1024, 256);
  const Aabb caster{dvec3(0.0, 5.0, 0.0), dvec3(1.0, 6.0, 1.0)};
  mask.add(dvec3(0.5, 0.0, 1.4));
  EXPECT_FALSE(mask.mayShadow(caster, 0.5));
  mask.add(dvec3(0.5, 0.0, 1.04));
  EXPECT_TRUE(mask.mayShadow(caster, 0.5));
}

// texelsRead: the texels a lookup at a receiver may read, against a brute-force count on the
// closed-form map (1024² texels over 100 m: texel coordinate (x / 50 + 1) · 512). A lookup at
// texel coordinate u reads the texels whose centres i + ½ lie within the reach of u along each
// axis (clamped to the map: CLAMP_TO_EDGE). The rectangle must hold every such texel of every
// receiver, and may exceed their bounds by at most two texels a side: a sub-cell (one texel here)
// forgets where in it the point lay, and the ends are rounded to whole texels.
TEST(ReceiverMask, TheTexelsReadHoldEveryTexelALookupAtAReceiverReads) {
  constexpr int kSize = 1024;
  const double reach = 2.5;
  ReceiverMask mask;
  mask.reset(overheadSetup(), kSize, 256);
  EXPECT_TRUE(mask.texelsRead(reach).empty());  // no receivers: no texel is read
  std::mt19937 random(11);
  std::uniform_real_distribution<double> coordinate(-20.0, 30.0);
  int lower[2] = {kSize, kSize}, upper[2] = {-1, -1};  // the texels read, inclusive
  for (int i = 0; i < 40; ++i) {
    const dvec3 p(coordinate(random), 0.0, i == 0 ? 49.99 : coordinate(random));  // one at the map's top edge
    mask.add(p);
    const double u[2] = {(p.x / 50.0 + 1.0) * 0.5 * kSize, (p.z / 50.0 + 1.0) * 0.5 * kSize};
    for (int axis = 0; axis < 2; ++axis)
      for (int t = -10; t < kSize + 10; ++t)
        if (std::abs(t + 0.5 - u[axis]) < reach) {
          const int texel = std::clamp(t, 0, kSize - 1);
          lower[axis] = std::min(lower[axis], texel);
          upper[axis] = std::max(upper[axis], texel);
        }
  }
  const TexelRect rect = mask.texelsRead(reach);
  EXPECT_LE(rect.x0, lower[0]);
  EXPECT_LE(rect.y0, lower[1]);
  EXPECT_GT(rect.x1, upper[0]);
  EXPECT_GT(rect.y1, upper[1]);
  EXPECT_GE(rect.x0, lower[0] - 2);
  EXPECT_GE(rect.y0, lower[1] - 2);
  EXPECT_LE(rect.x1, upper[0] + 1 + 2);
  EXPECT_LE(rect.y1, upper[1] + 1 + 2);
  EXPECT_EQ(rect.y1, kSize);  // the receiver at the top edge reads the last row
  EXPECT_LT(rect.texels(), static_cast<long long>(kSize) * kSize / 2);  // the receivers span half the map's width or less
  // A receiver the map cannot place may read any texel.
  ShadowSetup behind = overheadSetup();
  behind.worldToShadowClip[1][3] = 1.0;  // w = 1 + y
  mask.reset(behind, kSize, 256);
  mask.add(dvec3(0.0, 1.0, 0.0));
  EXPECT_LE(mask.texelsRead(reach).texels(), 10 * 10);  // one receiver: a few texels around it
  mask.add(dvec3(0.0, -2.0, 0.0));
  const TexelRect whole = mask.texelsRead(reach);
  EXPECT_EQ(whole.texels(), static_cast<long long>(kSize) * kSize);
}

// Which receivers read a texel (CasterOcclusion's test): a receiver at map texel coordinate u and
// depth z reads texel t when |t + 0.5 − u| < reach on both axes. Every such texel has a
// farthestReading at or beyond z — by at most a depth code (1 / 32767.5) when the receiver is the
// farthest within a texel of it — and is visited by forEachTexelRead; a texel farther than the
// reach plus two texels (a sub-cell and the rounding) from every receiver has none and is not
// visited. At 256 cells (one texel per sub-cell) and at 64 (four texels per sub-cell).
TEST(ReceiverMask, TheFarthestReceiverReadingATexelBoundsEveryLookupThatReadsIt) {
  constexpr int kSize = 1024;
  const double reach = 2.5, code = 1.0 / 32767.5;
  for (int cells : {256, 64}) {
    ReceiverMask mask;
    mask.reset(overheadSetup(), kSize, cells);
    EXPECT_FALSE(mask.farthestReading(500, 500, reach).has_value());  // no receivers
    std::mt19937 random(13);
    std::uniform_real_distribution<double> coordinate(-3.0, 3.0), height(-20.0, 20.0);
    struct Receiver {
      double u, v, depth;
    };
    std::vector<Receiver> receivers;
    for (int i = 0; i < 300; ++i) {
      const dvec3 p(coordinate(random), height(random), coordinate(random));
      mask.add(p);
      receivers.push_back({(p.x / 50.0 + 1.0) * 0.5 * kSize, (p.z / 50.0 + 1.0) * 0.5 * kSize, -p.y / 100.0});
    }
    std::vector<int> visits(static_cast<size_t>(kSize) * kSize, 0);
    mask.forEachTexelRead(reach, [&](int x, int y) { ++visits[static_cast<size_t>(y) * kSize + x]; });
    int read = 0, unread = 0;
    for (int y = 440; y < 584; ++y)
      for (int x = 440; x < 584; ++x) {
        double farthest = -std::numeric_limits<double>::infinity(), nearest = std::numeric_limits<double>::infinity();
        for (const Receiver& r : receivers) {
          const double dx = std::abs(x + 0.5 - r.u), dy = std::abs(y + 0.5 - r.v);
          if (dx < reach && dy < reach) farthest = std::max(farthest, r.depth);
          nearest = std::min(nearest, std::max(dx, dy));
        }
        const std::optional<double> bound = mask.farthestReading(x, y, reach);
        const int visited = visits[static_cast<size_t>(y) * kSize + x];
        if (std::isfinite(farthest)) {
          ++read;
          ASSERT_TRUE(bound.has_value()) << cells << " cells, texel " << x << ", " << y;
          EXPECT_GE(*bound, farthest) << cells << " cells, texel " << x << ", " << y;
          EXPECT_GT(visited, 0) << cells << " cells, texel " << x << ", " << y;
        }
        if (nearest > reach + 2.0 * kSize / (4.0 * cells) + 1.0) {
          ++unread;
          EXPECT_FALSE(bound.has_value()) << cells << " cells, texel " << x << ", " << y;
          EXPECT_EQ(visited, 0) << cells << " cells, texel " << x << ", " << y;
        }
      }
    EXPECT_GT(read, 1000);
    EXPECT_GT(unread, 1000);
    // One receiver alone: its texels read its depth, rounded up by at most a code.
    mask.reset(overheadSetup(), kSize, cells);
    mask.add(dvec3(0.3, 7.0, 0.3));
    const std::optional<double> alone = mask.farthestReading(static_cast<int>((0.3 / 50.0 + 1.0) * 0.5 * kSize), 
                                                             static_cast<int>((0.3 / 50.0 + 1.0) * 0.5 * kSize), reach);
    ASSERT_TRUE(alone.has_value());
    EXPECT_GE(*alone, -0.07);
    EXPECT_LE(*alone, -0.07 + 2.0 * code);
  }
}

}  // namespace
}  // namespace forest::shadows
