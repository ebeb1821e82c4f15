// Kept slices (shadows/kept_slices.hpp) against what they promise, each checked independently of
// the unit's own tests: the stability suite's invariants (B and the visible part inside the map as
// the GPU computes it), the texel size by finite differences of the map's coordinates, the matrix
// itself from frame to frame (a kept map places every world point where it did), and the
// extrapolated camera against its closed form.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "forest/shadows/casters.hpp"
#include "forest/shadows/focus_body.hpp"
#include "forest/shadows/kept_slices.hpp"
#include "forest/shadows/stability.hpp"

namespace forest::shadows {
namespace {

using glm::dvec2;
using glm::dvec3;

// A 1 km terrain-like scene, its receivers the lower 30 m, a camera 10 m up looking slightly down.
ShadowInput walkInput(const dvec3& position, double yawDeg) {
  ShadowInput in;
  in.camera.position = position;
  in.camera.yaw = glm::radians(yawDeg);
  in.camera.pitch = glm::radians(-5.0);
  in.camera.near = 0.2;
  in.camera.far = 300.0;
  in.camera.aspect = 16.0 / 9.0;
  in.sunDirection = dvec3(0.4, -0.8, 0.3);
  in.scene = Aabb{dvec3(-500.0, 0.0, -500.0), dvec3(500.0, 60.0, 500.0)};
  in.receivers = Aabb{dvec3(-500.0, 0.0, -500.0), dvec3(500.0, 30.0, 500.0)};
  in.mapSize = 2048;
  in.borderTexels = 2;
  return in;
}

// Texel side (world units per texel across the light) at p, by central differences of the map's
// coordinates — not the unit's Jacobian.
double texelSide(const ShadowSetup& setup, const dvec3& p, const dvec3& l, int mapSize) {
  const auto [u, v] = axesAcrossLight(glm::normalize(l));
  const double h = 1e-3;
  auto map = [&](const dvec3& q) { return dvec2(shadowMapCoordinates(setup, q)); };
  const dvec2 du = (map(p + h * u) - map(p - h * u)) / (2.0 * h), dv = (map(p + h * v) - map(p - h * v)) / (2.0 * h);
  const double mapAreaPerWorldArea = std::abs(du.x * dv.y - du.y * dv.x);
  const double texelArea = (2.0 / mapSize) * (2.0 / mapSize);
  return std::sqrt(texelArea / mapAreaPerWorldArea);
}

// The vertices of the part of the view that can be seen: V ∩ S ∩ R.
std::vector<dvec3> visibleVertices(const ShadowInput& in) {
  ConvexBody body = viewFrustumBody(in.camera);
  body.clip(in.scene);
  body.clip(*in.receivers);
  const auto vertices = body.vertices();
  return {vertices.begin(), vertices.end()};
}

void expectInvariants(const ShadowInput& in, ShadowMethod method, const ShadowSetup& setup, const std::string& where) {
  const StabilityReport report = checkSetupInvariants(in, method, setup);
  for (const InvariantCheck& check : report.checks) EXPECT_TRUE(check.passed) << where << ": " << check.name << ": " << check.detail;
  // What the GPU gets, the float matrix for positions relative to this frame's eye, places B's
  // vertices where the double world matrix does (to float32's rounding: 1e-4 of the map).
  for (const dvec3& p : setup.body.vertices()) {
    const glm::dvec4 h = glm::dmat4(setup.eyeRelativeToShadowClipF) * glm::dvec4(p - in.camera.position, 1.0);
    const dvec3 exact = shadowMapCoordinates(setup, p);
    EXPECT_NEAR(h.x / h.w, exact.x, 1e-4) << where;
    EXPECT_NEAR(h.y / h.w, exact.y, 1e-4) << where;
  }
}

const ShadowMethod kKeptMethods[] = {ShadowMethod::Uniform, ShadowMethod::Lispsm, ShadowMethod::Tsm};

TEST(ExtrapolatedCamera, ContinuesTheLastMotionAcrossTheYawWrap) {
  Camera last, now;
  last.position = dvec3(1.0, 2.0, 3.0);
  now.position = dvec3(1.5, 2.0, 2.0);
  last.yaw = std::numbers::pi - 0.01;  // the yaw wraps: the turn is +0.02, not −2π + 0.02
  now.yaw = -std::numbers::pi + 0.01;
  last.pitch = 0.1;
  now.pitch = 0.05;
  const Camera ahead = extrapolatedCamera(now, last, 4.0);
  EXPECT_NEAR(glm::distance(ahead.position, dvec3(1.5 + 4 * 0.5, 2.0, 2.0 - 4 * 1.0)), 0.0, 1e-12);
  EXPECT_NEAR(std::remainder(ahead.yaw - (now.yaw + 4 * 0.02), 2 * std::numbers::pi), 0.0, 1e-12);
  EXPECT_NEAR(ahead.pitch, 0.05 - 4 * 0.05, 1e-12);
}

// A first frame is the fresh fit, as without keeping; a still camera keeps it.
TEST(KeptSlices, AStillCameraKeepsItsMapAndAStableMethodIsNeverKept) {
  for (ShadowMethod method : kKeptMethods) {
    KeptSlices kept;
    SliceKeeping keeping;
    const ShadowInput in = walkInput(dvec3(0.0, 10.0, 0.0), 30.0);
    const ShadowSetup first = kept.setup(in, method, 0, KeepLimits{}, keeping);
    EXPECT_FALSE(keeping.kept);
    EXPECT_EQ(keeping.refit, "first");
    EXPECT_EQ(first.worldToShadowClip, computeShadowSetup(in, method).worldToShadowClip);
    for (int frame = 1; frame < 4; ++frame) {
      const ShadowSetup again = kept.setup(in, method, 0, KeepLimits{}, keeping);
      EXPECT_TRUE(keeping.kept) << kShadowMethodNames.name(method);
      EXPECT_EQ(keeping.keptFrames, frame);
      EXPECT_EQ(again.worldToShadowClip, first.worldToShadowClip) << kShadowMethodNames.name(method);
    }
  }
  KeptSlices kept;
  SliceKeeping keeping;
  for (int frame = 0; frame < 3; ++frame) {
    kept.setup(walkInput(dvec3(0.0, 10.0, 0.0), 30.0), ShadowMethod::UniformStable, 0, KeepLimits{}, keeping);
    EXPECT_FALSE(keeping.kept);
    EXPECT_EQ(keeping.refit, "stable");
  }
}

// A camera walking 0.2 m and turning 0.1° a frame: every setup keeps the invariants; a kept one
// places the world where the last frame's did, with texels within the limit of a fresh fit's.
TEST(KeptSlices, AWalkingCameraKeepsMapsThatHoldItsViewWithinTheTexelLimit) {
  const KeepLimits limits;
  for (ShadowMethod method : kKeptMethods) {
    KeptSlices kept;
    SliceKeeping keeping;
    ShadowSetup previous;
    int keptFrames = 0;
    for (int frame = 0; frame < 60; ++frame) {
      const double yaw = 30.0 + 0.1 * frame;
      const dvec3 position = dvec3(0.0, 10.0, 0.0) + 0.2 * frame * directionFromYawPitch(glm::radians(30.0), 0.0);
      const ShadowInput in = walkInput(position, yaw);
      const std::string where = fmt::format("{} frame {}", kShadowMethodNames.name(method), frame);
      const ShadowSetup setup = kept.setup(in, method, 0, limits, keeping);
      expectInvariants(in, method, setup, where);
      ShadowInput freshInput = in;
      const ShadowSetup fresh = computeShadowSetup(freshInput, method);
      for (const dvec3& p : visibleVertices(in)) {
        const double ratio = texelSide(setup, p, in.sunDirection, in.mapSize) / texelSide(fresh, p, in.sunDirection, in.mapSize);
        EXPECT_LE(ratio, limits.texelGrowth * (1.0 + 1e-4)) << where;
      }
      if (keeping.kept) {
        ++keptFrames;
        EXPECT_EQ(setup.worldToShadowClip, previous.worldToShadowClip) << where;
      }
      previous = setup;
    }
    // A steady walk is what the horizon predicts: most frames keep (at least one in two).
    EXPECT_GE(keptFrames, 30) << kShadowMethodNames.name(method);
  }
}

// Pure translation: a refit's map holds the focus body of every camera between now and the
// horizon (a translate of a convex body lies in the hull of its ends), so the uniform map — whose
// texels do not change with the camera — is kept for the horizon's frames after each refit.
TEST(KeptSlices, AUniformMapIsKeptForTheWholeHorizonOfAStraightWalk) {
  const KeepLimits limits;
  KeptSlices kept;
  SliceKeeping keeping;
  int sinceRefit = -1;
  for (int frame = 0; frame < 40; ++frame) {
    const dvec3 position = dvec3(0.0, 10.0, 0.0) + 0.5 * frame * directionFromYawPitch(glm::radians(30.0), 0.0);
    kept.setup(walkInput(position, 30.0), ShadowMethod::Uniform, 0, limits, keeping);
    if (frame >= 2 && sinceRefit >= 0 && sinceRefit < limits.horizonFrames - 1) {
      EXPECT_TRUE(keeping.kept) << "frame " << frame << ", " << sinceRefit << " after a refit: " << keeping.refit;
    }
    sinceRefit = keeping.kept ? sinceRefit + 1 : 0;
  }
}

TEST(KeptSlices, TheSunMovingBeyondTheLimitOrACameraCutRefits) {
  const KeepLimits limits;
  for (ShadowMethod method : kKeptMethods) {
    KeptSlices kept;
    SliceKeeping keeping;
    // A first frame (the fresh fit), a step (a refit with its margin), then the sun turned about
    // the vertical by half the limit: kept; by twice the limit: refitted.
    kept.setup(walkInput(dvec3(0.0, 10.0, 0.0), 30.0), method, 0, limits, keeping);
    ShadowInput in = walkInput(dvec3(0.1, 10.0, 0.0), 30.0);
    kept.setup(in, method, 0, limits, keeping);
    ASSERT_FALSE(keeping.kept);
    auto turned = [&](double deg) {
      const double a = glm::radians(deg);
      const dvec3 s = walkInput(dvec3(0.0), 0.0).sunDirection;
      return dvec3(std::cos(a) * s.x - std::sin(a) * s.z, s.y, std::sin(a) * s.x + std::cos(a) * s.z);
    };
    in.sunDirection = turned(0.5 * limits.sunDeg);
    kept.setup(in, method, 0, limits, keeping);
    EXPECT_TRUE(keeping.kept) << kShadowMethodNames.name(method);
    in.sunDirection = turned(2.0 * limits.sunDeg);
    kept.setup(in, method, 0, limits, keeping);
    EXPECT_FALSE(keeping.kept);
    EXPECT_EQ(keeping.refit, "sun");
    // A cut: 200 m away, facing the other way.
    ShadowInput cut = walkInput(dvec3(200.0, 10.0, -150.0), 210.0);
    cut.sunDirection = in.sunDirection;  // the sun of the refit before
    const ShadowSetup setup = kept.setup(cut, method, 0, limits, keeping);
    EXPECT_FALSE(keeping.kept);
    EXPECT_EQ(keeping.refit, "outside");
    expectInvariants(cut, method, setup, "after the cut");
  }
}

// The finest texel across the light, against closed forms: an orthographic map 100 m wide has
// 100 / size m texels everywhere; the projective map x' = x / 50w, y' = z / 50w with w = 1 + z/100
// (light straight down) has, on the axis x = 0, the Jacobian diag(1 / 50w, 1 / 50w²), whose
// largest singular value 1 / 50w gives texels of (2 / size) · 50w — not the mean side √(1/det).
TEST(FinestTexelSide, MatchesClosedFormsOfOrthographicAndProjectiveMaps) {
  const dvec3 down(0.0, -1.0, 0.0);
  const int size = 1000;
  ShadowSetup ortho;
  ortho.worldToShadowClip = glm::dmat4(0.0);
  ortho.worldToShadowClip[0][0] = 1.0 / 50.0;   // x → x'
  ortho.worldToShadowClip[2][1] = 1.0 / 50.0;   // z → y'
  ortho.worldToShadowClip[1][2] = -1.0 / 100.0;  // y → depth
  ortho.worldToShadowClip[3][3] = 1.0;
  const std::vector<dvec3> points{dvec3(-20.0, 0.0, 5.0), dvec3(30.0, 10.0, -40.0)};
  EXPECT_NEAR(finestTexelSide(ortho, size, points, down), 100.0 / size, 1e-12);

  ShadowSetup warped = ortho;
  warped.worldToShadowClip[2][3] = 1.0 / 100.0;  // w = 1 + z / 100
  const std::vector<dvec3> atW2{dvec3(0.0, 0.0, 100.0)}, both{dvec3(0.0, 0.0, 100.0), dvec3(0.0, 0.0, 0.0)};
  EXPECT_NEAR(finestTexelSide(warped, size, atW2, down), 2.0 / size * 50.0 * 2.0, 1e-12);
  EXPECT_NEAR(finestTexelSide(warped, size, both, down), 2.0 / size * 50.0, 1e-12);
  // A point the map cannot place (w ≤ 0) has no texel.
  const std::vector<dvec3> behind{dvec3(0.0, 0.0, -200.0)};
  EXPECT_TRUE(std::isinf(finestTexelSide(warped, size, behind, down)));
}

}  // namespace
}  // namespace forest::shadows
