// Shadow setup (thesis ch. 8, §9.2): n through the whole pipeline against eq. 8.10/8.11, and the
// invariants on the hard cases of DESIGN §6 and on random configurations, checked with the
// float32 matrix the GPU gets.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>

#include "forest/core/error.hpp"
#include "forest/core/polygon2d.hpp"
#include "forest/shadows/focus_body.hpp"
#include "forest/shadows/shadow_setup.hpp"
#include "forest/shadows/stability.hpp"

namespace forest::shadows {
namespace {

using glm::dvec3;

constexpr ShadowMethod kMethods[] = {ShadowMethod::Uniform, ShadowMethod::UniformStable, ShadowMethod::Lispsm, ShadowMethod::Tsm,
                                     ShadowMethod::TsmIterative};

Camera makeCamera(dvec3 position, double yawDeg, double pitchDeg, double fovyDeg, double aspect, double near,
                  double far) {
  Camera c;
  c.position = position;
  c.yaw = glm::radians(yawDeg);
  c.pitch = glm::radians(pitchDeg);
  c.fovy = glm::radians(fovyDeg);
  c.aspect = aspect;
  c.near = near;
  c.far = far;
  return c;
}

ShadowInput input(const Camera& camera, dvec3 sun, Aabb scene) {
  ShadowInput in;
  in.camera = camera;
  in.sunDirection = sun;
  in.scene = scene;
  return in;
}

Aabb hugeScene() { return {dvec3(-1e4), dvec3(1e4)}; }

TEST(LispsmN, PerpendicularViewMatchesEq810) {
  // View ⟂ light, V ⊂ S, z_n 0.1, z_f 70: n = z_n + √(z_n z_f) = 0.1 + √7 ≈ 2.7458.
  const Camera c = makeCamera({0, 0, 0}, 0, 0, 60, 16.0 / 9.0, 0.1, 70);
  const ShadowSetup s = computeShadowSetup(input(c, {0, -1, 0}, hugeScene()), ShadowMethod::Lispsm);
  EXPECT_NEAR(s.diagnostics.n, 0.1 + std::sqrt(7.0), 1e-3);
  EXPECT_NEAR(s.diagnostics.z0, -0.1, 1e-9);
  EXPECT_NEAR(s.diagnostics.z1, -70.0, 1e-6);
  EXPECT_NEAR(s.diagnostics.d, 69.9, 1e-6);
}

struct Eq811Case {
  double gammaDeg;
  double expectedN;
};

TEST(LispsmN, MatchesEq811AtThreeAngles) {
  // z_n 1, light-space depth d 100: n = (z_n + √(z_n (z_n + d sin γ))) / sin γ.
  for (const Eq811Case& k : {Eq811Case{90, 11.049876}, Eq811Case{45, 13.390079}, Eq811Case{10, 30.437516}}) {
    const double sinGamma = std::sin(glm::radians(k.gammaDeg));
    const double far = 1.0 + 100.0 / sinGamma;
    // A needle-thin frustum (fovy 1e-6 rad) pitched down by 90° − γ: B's light-space depth is 100.
    const Camera c = makeCamera({0, 0, 0}, 0, -(90.0 - k.gammaDeg), glm::degrees(1e-6), 1.0, 1.0, far);
    const ShadowSetup s = computeShadowSetup(input(c, {0, -1, 0}, hugeScene()), ShadowMethod::Lispsm);
    EXPECT_NEAR(s.diagnostics.d, 100.0, 1e-2) << k.gammaDeg;
    EXPECT_NEAR(s.diagnostics.n / k.expectedN, 1.0, 1e-4) << "γ = " << k.gammaDeg << "°, n = " << s.diagnostics.n;
  }
}

TEST(Tsm, EightyPercentRuleWorkedCase) {
  // TSM §6.2: λ = 2, δ' = 0.1, ξ = −0.6 → η = λδ'(1 + ξ) / (λ − 2δ' − λξ) = 0.08 / 3 = 0.0266667.
  EXPECT_NEAR(tsmProjectionDistance(2.0, 0.1, -0.6), 0.08 / 3.0, 1e-15);
  EXPECT_NEAR(tsmProjectionDistance(2.0, 0.1, -0.6), 0.0266667, 1e-7);
  // No finite q when the focus point lies beyond the 80% of λ the rule asks for.
  EXPECT_TRUE(std::isinf(tsmProjectionDistance(2.0, 1.7, -0.6)));
}

TEST(Tsm, TrapezoidMapsTopBaseAndFocusLines) {
  // Through the whole setup: the map's y of B's nearest footprint point (top line) is +1, of its
  // farthest (base line) −1 and of the focus point ξ = −0.6, all times the border's (1 − m);
  // depth is the linear light depth (TSM §4): affine in the world, B inside [−1, 1].
  for (double pitch : {-5.0, -30.0, -60.0}) {
    for (double elevation : {20.0, 50.0}) {
      const double e = glm::radians(elevation);
      const Camera c = makeCamera({3, 2, 7}, 20, pitch, 60, 16.0 / 9.0, 0.1, 300);
      ShadowInput in = input(c, {0.6 * std::cos(e), -std::sin(e), 0.8 * std::cos(e)}, {dvec3(-1000, -10, -1000), dvec3(1000, 60, 1000)});
      in.borderTexels = 2;
      const ShadowSetup s = computeShadowSetup(in, ShadowMethod::Tsm);
      const std::string where = "pitch " + std::to_string(pitch) + "° sun " + std::to_string(elevation) + "°";
      ASSERT_TRUE(s.linearDepth) << where;
      ASSERT_EQ(s.diagnostics.fallback, "") << where;
      const double keep = 1.0 - 2.0 * in.borderTexels / in.mapSize;
      double top = -2.0, base = 2.0, nearDepth = 2.0, farDepth = -2.0;
      for (const dvec3& v : s.body.vertices()) {
        const dvec3 m = shadowMapCoordinates(s, v);
        top = std::max(top, m.y);
        base = std::min(base, m.y);
        nearDepth = std::min(nearDepth, m.z);
        farDepth = std::max(farDepth, m.z);
        EXPECT_LE(std::abs(m.x), keep + 1e-9) << where;
      }
      EXPECT_NEAR(top, keep, 1e-9) << where;
      EXPECT_NEAR(base, -keep, 1e-9) << where;
      // Depth fills [−1, 1] less the float32 margin finish() keeps (the γ₄ rounding bound of the camera-relative row, ≲ 64·2⁻²⁴).
      EXPECT_GE(nearDepth, -1.0) << where;
      EXPECT_LE(farDepth, 1.0) << where;
      EXPECT_NEAR(nearDepth, -1.0, 64 * kFloatUnitRoundoff) << where;
      EXPECT_NEAR(farDepth, 1.0, 64 * kFloatUnitRoundoff) << where;
      // The focus point: 30% into the depth range of V ∩ S (the whole view here: V ⊂ S).
      ConvexBody visible = viewFrustumBody(c);
      visible.clip(in.scene);
      double nearest = 1e300, farthest = -1e300;
      for (const dvec3& v : visible.vertices()) {
        nearest = std::min(nearest, glm::dot(v - c.position, c.forward()));
        farthest = std::max(farthest, glm::dot(v - c.position, c.forward()));
      }
      const dvec3 focus = c.position + c.forward() * (nearest + in.tsmFocusShare * (farthest - nearest));
      // §6.2's 80% rule: the focus point lands 80% of the map's height below its top line.
      EXPECT_NEAR(shadowMapCoordinates(s, focus).y, (1.0 - 2.0 * 0.8) * keep, 1e-9) << where;
      // The focus region (B's footprint between the top line and the focus point's line) measured
      // here, on the map: B's vertices through each setup's matrix, their hull cut at the focus
      // point's y. The iterative variant (§6.2) must give it at least the 80% rule's area.
      auto focusArea = [&](const ShadowSetup& setup) {
        std::vector<glm::dvec2> points;
        for (const dvec3& v : setup.body.vertices()) points.push_back(glm::dvec2(shadowMapCoordinates(setup, v)));
        const std::vector<glm::dvec2> hull = convexHull(points);
        const double cut = shadowMapCoordinates(setup, focus).y;
        std::vector<glm::dvec2> above;  // Sutherland–Hodgman against y ≥ cut
        for (size_t i = 0; i < hull.size(); ++i) {
          const glm::dvec2 a = hull[i], b = hull[(i + 1) % hull.size()];
          if (a.y >= cut) above.push_back(a);
          if ((a.y >= cut) != (b.y >= cut)) above.push_back(a + (b - a) * ((cut - a.y) / (b.y - a.y)));
        }
        return polygonArea(above) / (4.0 * keep * keep);
      };
      const ShadowSetup iterative = computeShadowSetup(in, ShadowMethod::TsmIterative);
      const double ruleArea = focusArea(s), iterativeArea = focusArea(iterative);
      EXPECT_GT(ruleArea, 0.05) << where;
      EXPECT_GE(iterativeArea, ruleArea * (1.0 - 1e-9)) << where;
      EXPECT_NEAR(ruleArea, s.diagnostics.tsmFocusArea, 1e-6) << where;  // the diagnostic reports what the map shows
    }
  }
}

TEST(Tsm, ViewAlongTheLightFallsBackToTheUniformMap) {
  // Looking straight down under a noon sun: eye and centre of V ∩ S project to one point, there
  // is no centre line (§6.1's coincident centres): the map is L itself, still linear depth.
  const Camera c = makeCamera({0, 50, 0}, 0, -90, 60, 1.0, 0.1, 40);
  const ShadowSetup s = computeShadowSetup(input(c, {0, -1, 0}, hugeScene()), ShadowMethod::Tsm);
  EXPECT_FALSE(s.empty);
  EXPECT_TRUE(s.linearDepth);
  EXPECT_NE(s.diagnostics.fallback.find("no centre line"), std::string::npos) << s.diagnostics.fallback;
  const ShadowSetup uniform = computeShadowSetup(input(c, {0, -1, 0}, hugeScene()), ShadowMethod::Uniform);
  for (const dvec3& v : s.body.vertices()) {
    const dvec3 a = shadowMapCoordinates(s, v), b = shadowMapCoordinates(uniform, v);
    EXPECT_NEAR(std::max(std::abs(a.x), std::abs(a.y)), std::max(std::abs(b.x), std::abs(b.y)), 1e-9);
  }
}

// uniform-stable along a walk whose far distance changes every frame (as the visible set's z_f
// does): a world point keeps its fractional texel position between the documented radius steps
// (2^(k/4) m, hysteresis √2), and camera moves shift the map by whole texels only.
TEST(UniformStable, TexelGridStaysFixedBetweenRadiusStepsAlongAWalk) {
  const Aabb scene{dvec3(-2000, -10, -2000), dvec3(2000, 150, 2000)};
  const dvec3 sun = glm::normalize(dvec3(0.5, -0.45, -0.4));
  const std::vector<dvec3> probes = {{-120, 5, 80}, {-160, 12, 60}, {-90, 0, 150}, {-200, 30, 20}};
  std::optional<double> previous;
  glm::dvec2 lastTexel[4];
  double lastRadius = 0.0;
  int steps = 0, checked = 0;
  for (int k = 0; k < 200; ++k) {
    // Walk forward, turn, and let far follow a jumpy z_f (550–650 m, jumps of ~9%).
    Camera c = makeCamera({-150.0 + 0.8 * k, 8.0, 120.0 - 0.5 * k}, 210.0 + 0.7 * k, -2.0, 60, 16.0 / 9.0, 0.2,
                          600.0 + 50.0 * std::sin(0.3 * k) + (k % 17 == 0 ? -60.0 : 0.0));
    ShadowInput in = input(c, sun, scene);
    in.carried = previous.value_or(0.0);  // MethodHistory: what the last frame left
    const ShadowSetup s = computeShadowSetup(in, ShadowMethod::UniformStable);
    const double radius = s.diagnostics.stableRadius;
    // The documented steps: R is a power of 2^(1/4) m, covers the view's sphere, at most √2·2^(1/4) of it.
    const double quarterOctaves = 4.0 * std::log2(radius);
    EXPECT_NEAR(quarterOctaves, std::round(quarterOctaves), 1e-9) << k;
    for (int i = 0; i < 4; ++i) {
      const glm::dvec2 texel = (glm::dvec2(shadowMapCoordinates(s, probes[static_cast<size_t>(i)])) + 1.0) * (0.5 * in.mapSize);
      if (k > 0 && radius == lastRadius) {
        const glm::dvec2 shift = texel - lastTexel[i];
        EXPECT_NEAR(shift.x, std::round(shift.x), 1e-6) << "frame " << k << " probe " << i;
        EXPECT_NEAR(shift.y, std::round(shift.y), 1e-6) << "frame " << k << " probe " << i;
        ++checked;
      }
      lastTexel[i] = texel;
    }
    steps += k > 0 && radius != lastRadius ? 1 : 0;
    lastRadius = radius;
    previous = radius;
  }
  // far swings ±8% around 600 m plus 10% dips: within the √2 hysteresis, R steps rarely.
  EXPECT_LE(steps, 2);
  EXPECT_GT(checked, 700);
}

TEST(LispsmN, BareFormulaAndMisprintGuard) {
  EXPECT_NEAR(lispsmNearDistance(69.9, -0.1, -70.0), 0.1 + std::sqrt(7.0), 1e-12);
  EXPECT_TRUE(std::isinf(lispsmNearDistance(10.0, -1.0, -1.0)));  // z1 = z0: the misprinted case
}

TEST(LispsmN, MonotoneInGammaAndFadesContinuously) {
  double previousN = 0.0, previousWarp = -1.0;
  for (int step = 8900; step >= 0; --step) {
    const double gamma = 0.01 * step;
    const Camera c = makeCamera({0, 1, 0}, 0, -(90.0 - gamma), 60, 1.5, 0.1, 70);
    const ShadowSetup s = computeShadowSetup(input(c, {0, -1, 0}, hugeScene()), ShadowMethod::Lispsm);
    EXPECT_GE(s.diagnostics.n, previousN * (1 - 1e-9)) << gamma;
    if (s.diagnostics.warp == 0.0) {
      // §8.3: without a warp LiSPSM is the uniform map — B's vertices land where uniform puts them.
      const ShadowSetup uniform = computeShadowSetup(input(c, {0, -1, 0}, hugeScene()), ShadowMethod::Uniform);
      for (const dvec3& v : s.body.vertices())
        ASSERT_NEAR(glm::length(shadowMapCoordinates(s, v) - shadowMapCoordinates(uniform, v)), 0.0, 1e-9) << gamma;
    }
    if (previousWarp >= 0.0) {
      // 1/n changes by at most 2% of its 89° value between angles 0.01° apart.
      EXPECT_LE(std::abs(s.diagnostics.warp - previousWarp), 0.02 / 2.7) << gamma;
    }
    previousN = s.diagnostics.n;
    previousWarp = s.diagnostics.warp;
  }
  EXPECT_EQ(previousWarp, 0.0);  // γ = 0: no warp left
}

void expectInvariants(const ShadowInput& in, const std::string& name) {
  for (ShadowMethod method : kMethods) {
    const ShadowSetup s = computeShadowSetup(in, method);
    const StabilityReport report = checkSetupInvariants(in, method, s);
    for (const InvariantCheck& check : report.checks)
      EXPECT_TRUE(check.passed) << name << " / " << kShadowMethodNames.name(method) << ": " << check.name << ": " << check.detail;
    if (!s.empty) {
      EXPECT_GT(s.diagnostics.bodyVertices, 0u) << name;
    }
  }
}

TEST(ShadowSetupInvariants, HardCases) {
  const Aabb scene{dvec3(-500, -20, -500), dvec3(500, 60, 500)};
  const dvec3 eye(10, 5, 10);
  struct Case {
    std::string name;
    Camera camera;
    dvec3 sun;
    Aabb scene;
  };
  const double tiny = glm::degrees(1e-7), small = glm::degrees(1e-3);
  std::vector<Case> cases = {
      {"light parallel to view", makeCamera(eye, 0, -90, 60, 1.5, 0.1, 70), {0, -1, 0}, scene},
      {"light anti-parallel to view", makeCamera(eye, 0, 90, 60, 1.5, 0.1, 70), {0, -1, 0}, scene},
      {"light 1e-7 rad from view", makeCamera(eye, 0, -90 + tiny, 60, 1.5, 0.1, 70), {0, -1, 0}, scene},
      {"light 1e-3 rad from view", makeCamera(eye, 0, -90 + small, 60, 1.5, 0.1, 70), {0, -1, 0}, scene},
      {"view straight up, sun low", makeCamera(eye, 0, 90, 60, 1.5, 0.1, 70), {1, -0.01, 0}, scene},
      {"sun at 0.1° elevation", makeCamera(eye, 30, -5, 60, 1.5, 0.1, 70),
       {std::cos(glm::radians(0.1)), -std::sin(glm::radians(0.1)), 0}, scene},
      {"sun at 0.5° elevation behind", makeCamera(eye, 0, 0, 60, 1.5, 0.1, 70),
       {0, -std::sin(glm::radians(0.5)), -std::cos(glm::radians(0.5))}, scene},
      {"near 1e-4, far 1e5", makeCamera(eye, 20, -10, 60, 1.5, 1e-4, 1e5), {0.3, -0.8, 0.2}, scene},
      {"camera 1e6 m from the origin", makeCamera({1e6, 5, -1e6}, 45, -10, 60, 1.5, 0.1, 70), {0.3, -0.8, 0.2},
       Aabb{dvec3(1e6 - 500, -20, -1e6 - 500), dvec3(1e6 + 500, 60, -1e6 + 500)}},
      {"camera outside S looking away", makeCamera({0, 5, 900}, 180, 0, 60, 1.5, 0.1, 70), {0.3, -0.8, 0.2}, scene},
      {"flat scene box", makeCamera(eye, 0, -20, 60, 1.5, 0.1, 70), {0.3, -0.8, 0.2},
       Aabb{dvec3(-500, 0, -500), dvec3(500, 0, 500)}},
      {"fov 0.5°", makeCamera(eye, 0, -5, 0.5, 1.5, 0.1, 70), {0.3, -0.8, 0.2}, scene},
      {"fov 170°", makeCamera(eye, 0, -5, 170, 1.5, 0.1, 70), {0.3, -0.8, 0.2}, scene},
      {"aspect 10", makeCamera(eye, 0, -5, 60, 10, 0.1, 70), {0.3, -0.8, 0.2}, scene},
      {"unnormalised sun", makeCamera(eye, 0, -5, 60, 1.5, 0.1, 70), {300, -800, 200}, scene},
  };
  for (const Case& c : cases) expectInvariants(input(c.camera, c.sun, c.scene), c.name);
  // Camera outside S looking away: nothing to shadow, reported as such.
  const ShadowSetup away = computeShadowSetup(input(cases[9].camera, cases[9].sun, scene), ShadowMethod::Lispsm);
  EXPECT_TRUE(away.empty);
  EXPECT_EQ(away.diagnostics.fallback, "empty focus body");
}

TEST(ShadowSetupInput, InvalidInputIsRejected) {
  const Camera c = makeCamera({0, 0, 0}, 0, 0, 60, 1.5, 0.1, 70);
  EXPECT_THROW(computeShadowSetup(input(c, {0, 0, 0}, hugeScene()), ShadowMethod::Lispsm), InputError);
  EXPECT_THROW(computeShadowSetup(input(c, {0, std::nan(""), 0}, hugeScene()), ShadowMethod::Lispsm), InputError);
  Camera bad = c;
  bad.far = bad.near;
  EXPECT_THROW(computeShadowSetup(input(bad, {0, -1, 0}, hugeScene()), ShadowMethod::Lispsm), InputError);
  EXPECT_THROW(kShadowMethodNames.parse("psm"), InputError);
}

}  // namespace
}  // namespace forest::shadows
