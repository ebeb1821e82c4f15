// The receiver mask (shadows::ReceiverMask, Bittner et al. 2011 §4) on a map whose geometry is a
// closed form: the sun straight down, map x = world x / 50, map y = world z / 50, depth = −y / 100
// (higher is nearer the light), 1024² texels over 100 m (0.098 m per texel), 256² cells.
#include <gtest/gtest.h>

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
  EXPECT_TRUE(mask.mayShadow(Aabb{dvec3(30, 5, 30), dvec3(31, 6, 31)}, 0.5));
}

}  // namespace
}  // namespace forest::shadows
