// Shadow setup (thesis ch. 8, §9.2): n through the whole pipeline against eq. 8.10/8.11, and the
// invariants on the hard cases of DESIGN §6 and on random configurations, checked with the
// float32 matrix the GPU gets.
#include <gtest/gtest.h>

#include "forest/core/error.hpp"
#include "forest/shadows/shadow_setup.hpp"
#include "forest/shadows/stability.hpp"

namespace forest::shadows {
namespace {

using glm::dvec3;

constexpr ShadowMethod kMethods[] = {ShadowMethod::Uniform, ShadowMethod::UniformStable, ShadowMethod::Lispsm};

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
    EXPECT_LE(s.diagnostics.n, kLispsmCapFactor * s.diagnostics.d * (1 + 1e-12));
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
      EXPECT_TRUE(check.passed) << name << " / " << shadowMethodName(method) << ": " << check.name << ": " << check.detail;
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
  EXPECT_THROW(parseShadowMethod("psm"), InputError);
}

}  // namespace
}  // namespace forest::shadows
