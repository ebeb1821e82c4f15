// NearSlab (CHC++ §3.6 made exact for boxes beside the eye): a box meets the near slab exactly
// when the view frustum's face at z_n — sampled densely, brute force — reaches into it, within the
// margins NearSlab states; closed-form cases beside, in front of and at the corner of the near
// rectangle; empty and flat boxes.
#include <gtest/gtest.h>

#include <cmath>

#include "forest/core/camera.hpp"
#include "forest/core/near_slab.hpp"
#include "forest/core/random.hpp"

namespace forest {
namespace {

using glm::dvec3;

constexpr int kSamples = 96;  // per side of the sampled near rectangle

// Points of the frustum's cross-section at eye depth `depth`: kSamples² on a grid, edges included.
template <class Visit>
void forEachCrossSectionPoint(const Camera& c, double depth, const Visit& visit) {
  const double halfHeight = depth * std::tan(0.5 * c.fovy), halfWidth = halfHeight * c.aspect;
  for (int i = 0; i < kSamples; ++i)
    for (int j = 0; j < kSamples; ++j) {
      const double u = -1.0 + 2.0 * i / (kSamples - 1), v = -1.0 + 2.0 * j / (kSamples - 1);
      visit(c.position + depth * c.forward() + u * halfWidth * c.right() + v * halfHeight * c.up());
    }
}

// Whether a sampled point of the slab's two faces lies in the box grown by `grow`.
bool sampledSlabMeets(const Camera& c, const Aabb& box, double grow) {
  bool hit = false;
  for (double depth : {c.near, c.near * (1.0 + NearSlab::kDepth)})
    forEachCrossSectionPoint(c, depth, [&](const dvec3& p) { hit = hit || box.contains(p, grow); });
  return hit;
}

Camera frontCamera() {
  Camera c;
  c.aspect = 16.0 / 9.0;
  c.near = 0.1;
  return c;  // at the origin, looking along −z
}

TEST(NearSlab, ABoxBesideTheEyeThatReachesBehindTheNearPlaneOutsideTheViewIsSafeToQuery) {
  const NearSlab slab(frontCamera());
  // 0.5 m to the right, from 0.5 m behind the eye to 6 m ahead: its nearest corner is behind the
  // near plane (CHC++'s test would call it visible), but the near rectangle ends at x = 0.103.
  EXPECT_FALSE(slab.meets({dvec3(0.5, -1, -6), dvec3(3, 1, 0.5)}));
  // Beyond the slab, straight ahead.
  EXPECT_FALSE(slab.meets({dvec3(-1, -1, -3), dvec3(1, 1, -0.2)}));
  // Behind the eye.
  EXPECT_FALSE(slab.meets({dvec3(-1, -1, 0.2), dvec3(1, 1, 3)}));
}

TEST(NearSlab, ABoxTheNearRectangleCutsMeetsIt) {
  const Camera c = frontCamera();
  const NearSlab slab(c);
  EXPECT_TRUE(slab.meets({dvec3(-0.01, -0.01, -0.2), dvec3(0.01, 0.01, -0.05)}));  // through its middle
  // A box 2 µm wide around the rectangle's top-right corner.
  const double h = c.near * std::tan(0.5 * c.fovy), w = h * c.aspect;
  const dvec3 corner(w, h, -c.near);
  EXPECT_TRUE(slab.meets({corner - dvec3(1e-6), corner + dvec3(1e-6)}));
  // A flat box (a square on the near plane) and a point box in the rectangle.
  EXPECT_TRUE(slab.meets({dvec3(-0.02, -0.02, -c.near), dvec3(0.02, 0.02, -c.near)}));
  EXPECT_TRUE(slab.meets({dvec3(0.01, 0.0, -c.near), dvec3(0.01, 0.0, -c.near)}));
}

TEST(NearSlab, TheMarginIsWhatItStates) {
  // Boxes right of the rectangle's edge x = w: the slab's far face reaches w (1 + k) and the box
  // is grown by k z_n, so x0 < w (1 + k) + k z_n meets it and x0 beyond does not.
  const Camera c = frontCamera();
  const NearSlab slab(c);
  const double k = NearSlab::kDepth, w = c.near * std::tan(0.5 * c.fovy) * c.aspect, edge = w * (1.0 + k) + k * c.near;
  EXPECT_TRUE(slab.meets({dvec3(edge - 0.01 * k * c.near, -0.01, -0.5), dvec3(1, 0.01, 0.5)}));
  EXPECT_FALSE(slab.meets({dvec3(edge + 0.01 * k * c.near, -0.01, -0.5), dvec3(1, 0.01, 0.5)}));
}

TEST(NearSlab, AnEmptyBoxMeetsNothing) {
  EXPECT_FALSE(NearSlab(frontCamera()).meets(Aabb{}));
}

// Random cameras (any orientation, z_n from 1 mm to 1 m) and boxes around the near rectangle:
// wherever a sampled point of the slab lies in the box, meets() is true (it never lets a box that
// the near plane cuts be queried); and wherever meets() is true, a sample lies in the box grown by
// the stated margin plus the sample spacing (it does not call boxes far from the slab visible).
TEST(NearSlab, AgreesWithDenseSamplingOverRandomCamerasAndBoxes) {
  SplitMix64 random(20261204);
  int met = 0, missed = 0;
  for (int trial = 0; trial < 600; ++trial) {
    Camera c;
    c.position = dvec3(random.uniform(-100, 100), random.uniform(-10, 10), random.uniform(-100, 100));
    c.yaw = random.uniform(-3.1, 3.1);
    c.pitch = random.uniform(-1.5, 1.5);
    c.roll = random.uniform(-0.5, 0.5);
    c.fovy = glm::radians(random.uniform(20.0, 100.0));
    c.aspect = random.uniform(0.5, 2.5);
    c.near = std::pow(10.0, random.uniform(-3.0, 0.0));
    c.far = 1000.0 * c.near;
    const NearSlab slab(c);
    const double halfHeight = c.near * std::tan(0.5 * c.fovy), halfWidth = halfHeight * c.aspect;
    // A box of 0.05–3 rectangle sizes, centred within 2 rectangle sizes of the rectangle's centre.
    const double size = std::max(halfWidth, halfHeight);
    const dvec3 centre = c.position + c.near * c.forward() +
                         size * dvec3(random.uniform(-2, 2), random.uniform(-2, 2), random.uniform(-2, 2));
    const dvec3 half = size * dvec3(random.uniform(0.05, 3), random.uniform(0.05, 3), random.uniform(0.05, 3));
    const Aabb box{centre - half, centre + half};
    const bool meets = slab.meets(box);
    (meets ? met : missed)++;
    if (sampledSlabMeets(c, box, 0.0)) {
      EXPECT_TRUE(meets) << "trial " << trial << ": the near rectangle reaches into the box, which must not be queried";
    }
    if (meets) {
      // A point X of the slab in the grown box: moved along its eye ray onto the slab's nearer
      // face it shifts by ≤ k·|X − eye| ≤ k·(z_n + diagonal) and then lies within half a sample
      // diagonal of a sample: derived, not measured.
      const double k = NearSlab::kDepth, diagonal = std::hypot(halfWidth, halfHeight) * (1.0 + k);
      const double spacing = 2.0 * diagonal / (kSamples - 1);
      const double grow = k * c.near + k * (c.near + diagonal) + spacing;
      EXPECT_TRUE(sampledSlabMeets(c, box, grow)) << "trial " << trial << ": no sample of the slab within " << grow << " of the box";
    }
  }
  // Both outcomes occur often enough for the two checks to mean something.
  EXPECT_GT(met, 100);
  EXPECT_GT(missed, 100);
}

}  // namespace
}  // namespace forest
