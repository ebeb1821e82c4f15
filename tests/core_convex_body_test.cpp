// Convex bodies (thesis §9.2.2): clipping closes holes, extrusion and hull with a point give the
// expected solids, empty and flat results are represented, and results do not depend on where
// in the world the body is (relative tolerances).
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "forest/core/camera.hpp"
#include "forest/core/convex_body.hpp"
#include "forest/core/frustum.hpp"

namespace forest {
namespace {

using glm::dvec3;

Aabb box(dvec3 min, dvec3 max) { return {min, max}; }

TEST(ConvexBody, BoxHasSixFacesAndItsVolume) {
  const ConvexBody b = ConvexBody::fromBox(box({0, 0, 0}, {2, 3, 4}));
  EXPECT_EQ(b.polygons().size(), 6u);
  EXPECT_EQ(b.vertices().size(), 8u);
  EXPECT_NEAR(b.volume(), 24.0, 1e-12);
  EXPECT_TRUE(b.isClosed());
}

TEST(ConvexBody, ClipByPlaneClosesTheHole) {
  ConvexBody b = ConvexBody::fromBox(box({0, 0, 0}, {2, 2, 2}));
  b.clip(Plane::through({1, 1, 1}, glm::normalize(dvec3(1, 1, 1))));  // keeps x+y+z ≤ 3
  EXPECT_TRUE(b.isClosed());
  EXPECT_NEAR(b.volume(), 4.0, 1e-12);  // the plane through the centre halves the cube
  EXPECT_EQ(b.vertices().size(), 6u + 6u - 0u - 2u);  // 6 hexagon points + 4 remaining corners
}

TEST(ConvexBody, ClipAwayEverythingIsEmpty) {
  ConvexBody b = ConvexBody::fromBox(box({0, 0, 0}, {1, 1, 1}));
  b.clip(Plane{{1, 0, 0}, 5.0});  // keeps x ≤ −5
  EXPECT_TRUE(b.empty());
  EXPECT_EQ(b.volume(), 0.0);
  b.clip(box({-1, -1, -1}, {1, 1, 1}));
  EXPECT_TRUE(b.empty());
}

TEST(ConvexBody, FlatSceneBoxGivesAFlatBody) {
  ConvexBody frustumLike = ConvexBody::fromBox(box({-5, -5, -5}, {5, 5, 5}));
  frustumLike.clip(box({-10, 0, -10}, {10, 0, 10}));  // a scene box with zero height
  ASSERT_FALSE(frustumLike.empty());
  EXPECT_TRUE(frustumLike.isFlat());
  EXPECT_EQ(frustumLike.vertices().size(), 4u);
  EXPECT_EQ(frustumLike.bounds().extent().y, 0.0);
}

TEST(ConvexBody, ExtrusionAlongDirectionReachesTheBox) {
  ConvexBody b = ConvexBody::fromBox(box({-1, 0, -1}, {1, 1, 1}));
  const Aabb scene = box({-10, -10, -10}, {10, 10, 10});
  b.extrude({0, 1, 0}, scene);
  b.clip(scene);
  EXPECT_TRUE(b.isClosed());
  EXPECT_NEAR(b.volume(), 2.0 * 2.0 * 10.0, 1e-9);
  EXPECT_NEAR(b.bounds().max.y, 10.0, 1e-12);
  EXPECT_NEAR(b.bounds().min.y, 0.0, 1e-12);
}

TEST(ConvexBody, ObliqueExtrusionIsAPrism) {
  ConvexBody b = ConvexBody::fromBox(box({0, 0, 0}, {1, 1, 1}));
  const Aabb scene = box({-100, -100, -100}, {100, 5, 100});
  b.extrude({1, 1, 0}, scene);
  b.clip(scene);
  EXPECT_TRUE(b.isClosed());
  // Depth 1 in z times the x–y section: the unit square swept along (1, 1), cut at y = 5:
  // width 1 + y for y ∈ [0, 1], width 2 for y ∈ [1, 5] → 1.5 + 8 = 9.5.
  EXPECT_NEAR(b.volume(), 9.5, 1e-9);
}

TEST(ConvexBody, FlatBodyExtrudesToAPrism) {
  ConvexBody flat = ConvexBody::fromBox(box({0, 0, 0}, {2, 0, 3}));
  ASSERT_TRUE(flat.isFlat());
  const Aabb scene = box({-10, -10, -10}, {10, 4, 10});
  flat.extrude({0, 1, 0}, scene);
  flat.clip(scene);
  EXPECT_NEAR(flat.volume(), 2.0 * 3.0 * 4.0, 1e-9);
}

TEST(ConvexBody, HullWithPointAddsAnApex) {
  ConvexBody b = ConvexBody::fromBox(box({0, 0, 0}, {1, 1, 1}));
  b.hullWithPoint({0.5, 3.0, 0.5});
  EXPECT_TRUE(b.isClosed());
  EXPECT_EQ(b.vertices().size(), 9u);
  EXPECT_NEAR(b.volume(), 1.0 + 2.0 / 3.0, 1e-12);  // cube + pyramid of height 2 on a unit base
  const double before = b.volume();
  b.hullWithPoint({0.5, 0.5, 0.5});  // inside: no change
  EXPECT_EQ(b.volume(), before);
}

// A camera off the origin, turned and tilted, with the given far distance.
Camera tiltedCamera(double far) {
  Camera c;
  c.position = {3, 2, 1};
  c.yaw = 0.4;
  c.pitch = 0.2;
  c.near = 0.5;
  c.far = far;
  c.aspect = 1.5;
  return c;
}

TEST(ConvexBody, FrustumCornersComeFromTheInverseViewProjection) {
  const Camera c = tiltedCamera(20.0);
  const ConvexBody v = ConvexBody::fromInverseViewProjection(glm::inverse(c.projection() * c.view()));
  EXPECT_TRUE(v.isClosed());
  EXPECT_EQ(v.vertices().size(), 8u);
  // Volume of a frustum: h/3 (A1 + A2 + √(A1 A2)), A = (2 z tan(fovy/2))² · aspect.
  const double t = std::tan(c.fovy / 2);
  const double a1 = 4 * c.near * c.near * t * t * c.aspect, a2 = 4 * c.far * c.far * t * t * c.aspect;
  EXPECT_NEAR(v.volume(), (c.far - c.near) / 3 * (a1 + a2 + std::sqrt(a1 * a2)), 1e-9);
  // A point on the view axis is inside every face plane.
  const dvec3 inside = c.position + 5.0 * c.forward();
  for (const Polygon& p : v.polygons()) EXPECT_LT(Plane::through(p[0], polygonNormal(p)).signedDistance(inside), 0.0);
}

// Frustum::contains (a receiver inside the view skips its clip): against each corner projected by
// the camera's own matrices (inside: |x|, |y| ≤ w and 0 ≤ z ≤ w in clip space, reversed-Z or not),
// over random boxes near, across and outside the view.
TEST(Frustum, ContainsExactlyTheBoxesWhoseCornersAllProjectInside) {
  const Camera c = tiltedCamera(40.0);
  const Frustum frustum(c);
  const glm::dmat4 clip = c.projection() * c.view();
  std::uint64_t state = 12345;
  auto uniform = [&](double lo, double hi) {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return lo + (hi - lo) * static_cast<double>(state >> 11) / 9007199254740992.0;
  };
  int inside = 0, outside = 0;
  for (int k = 0; k < 20000; ++k) {
    const dvec3 centre = c.position + uniform(-5.0, 45.0) * c.forward() + dvec3(uniform(-20, 20), uniform(-15, 15), uniform(-20, 20));
    const dvec3 half(uniform(0.0, 3.0), uniform(0.0, 3.0), uniform(0.0, 3.0));
    const Aabb box{centre - half, centre + half};
    bool allInside = true;
    for (int i = 0; i < 8; ++i) {
      const glm::dvec4 h = clip * glm::dvec4(box.corner(i), 1.0);
      const double w = h.w, eps = 1e-9 * std::abs(w);
      allInside = allInside && std::abs(h.x) <= w + eps && std::abs(h.y) <= w + eps && h.z >= -eps && h.z <= w + eps;
    }
    // Boxes within a hair of a plane may go either way; the rest must agree.
    if (frustum.contains(box) != allInside) {
      double margin = 1e300;
      for (int i = 0; i < 8; ++i)
        for (const Plane& plane : frustum.planes()) margin = std::min(margin, std::abs(plane.signedDistance(box.corner(i))));
      EXPECT_LT(margin, 1e-9) << "box " << k;
    }
    (allInside ? inside : outside) += 1;
  }
  EXPECT_GT(inside, 1000);
  EXPECT_GT(outside, 1000);
}

TEST(ConvexBody, ClipToleranceFollowsTheKeptPartNotTheCutAway) {
  // A frustum 4e4 m deep clipped to a scene box 5 mm thin (random stability case #750732): with a
  // tolerance relative to the frustum (4e-5 m) vertices 5e-5 m outside the box survived.
  Camera c;
  c.position = {-612.81292016380007, -40.377139250636532, -316.40969753122613};
  c.yaw = 0.27169414726098501;
  c.pitch = -0.91481377968368349;
  c.roll = -0.74094473506611869;
  c.fovy = 0.50112810276411868;
  c.aspect = 1.2690583380324187;
  c.near = 0.20507990453695593;
  c.far = 40047.909135164235;
  const Aabb scene = box({-612.81542526569058, -44.023263843664829, -320.84713184499054},
                         {-612.81046984503712, -38.229919773378008, -304.8104914997985});
  ConvexBody v = ConvexBody::fromInverseViewProjection(glm::inverse(c.projection() * c.view()));
  v.clip(scene);
  ASSERT_FALSE(v.empty());
  EXPECT_TRUE(v.isClosed());
  const double tolerance = v.tolerance();
  EXPECT_LT(tolerance, 1e-7);
  for (const dvec3& p : v.vertices()) EXPECT_TRUE(scene.contains(p, tolerance)) << p.x << " " << p.y << " " << p.z;
}

TEST(ConvexBody, SameResultFarFromTheOrigin) {
  std::vector<double> volumes;
  for (double origin : {0.0, 1e6}) {
    const dvec3 o(origin, 0.0, -origin);
    ConvexBody b = ConvexBody::fromBox(box(o + dvec3(-1, 0, -1), o + dvec3(1, 1, 1)));
    const Aabb scene = box(o + dvec3(-10, -10, -10), o + dvec3(10, 10, 10));
    b.extrude({0.3, 1, 0.2}, scene);
    b.clip(scene);
    b.clip(Plane::through(o, glm::normalize(dvec3(1, 0, 1))));
    EXPECT_TRUE(b.isClosed()) << origin;
    volumes.push_back(b.volume());
  }
  EXPECT_GT(volumes[0], 1.0);
  EXPECT_NEAR(volumes[1], volumes[0], 1e-6 * volumes[0]);
}

}  // namespace
}  // namespace forest
