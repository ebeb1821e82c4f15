// Analytic aliasing (thesis §8.2): the per-point error against eq. 8.9 and eq. 8.2, the classic
// numbers for light ⟂ view at z_f/z_n = 100, and LiSPSM never worse than uniform for γ ≥ 30°.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "forest/core/random.hpp"
#include "forest/shadows/aliasing.hpp"

namespace forest::shadows {
namespace {

using glm::dvec3;

// Light straight down, camera looking level along −z from the origin, V ⊂ S, no border: the
// thesis' optimal case (view parallel to the map plane), γ = 90°.
ShadowInput perpendicularCase(double near, double far) {
  ShadowInput in;
  in.camera.position = {0, 0, 0};
  in.camera.fovy = glm::radians(60.0);
  in.camera.aspect = 4.0 / 3.0;
  in.camera.near = near;
  in.camera.far = far;
  in.sunDirection = {0, -1, 0};
  in.scene = {dvec3(-1e4), dvec3(1e4)};
  in.borderTexels = 0;
  return in;
}

// Eq. 8.9.
double eq89(double z, double zn, double zf, double n) {
  return (z - zn + n) * (z - zn + n) * (zf - zn) / (z * n * (n + zf - zn));
}

TEST(Aliasing, LispsmAtNinetyDegreesIsEq89) {
  const ShadowInput in = perpendicularCase(1.0, 100.0);
  const ShadowSetup s = computeShadowSetup(in, ShadowMethod::Lispsm);
  ASSERT_EQ(glm::dot(in.camera.forward(), in.sunDirection), 0.0);
  const double n = 1.0 / s.diagnostics.warp;  // the n actually used (after the fade, ≈ n_opt)
  EXPECT_NEAR(n / 11.0, 1.0, 2e-4);
  for (double z : {1.0, 1.5, 3.0, 11.0, 30.0, 70.0, 100.0}) {
    const double e = perspectiveAliasing(s, in.camera, in.camera.position + z * in.camera.forward());
    EXPECT_NEAR(e / eq89(z, 1.0, 100.0, n), 1.0, 1e-6 + s.diagnostics.floatShrink) << "z = " << z;
  }
  // Eq. 8.10: at n_opt the errors at the near and the far plane are equal.
  const double nOpt = 1.0 + std::sqrt(100.0);
  EXPECT_NEAR(eq89(1.0, 1.0, 100.0, nOpt) / eq89(100.0, 1.0, 100.0, nOpt), 1.0, 1e-12);
  const double nearError = perspectiveAliasing(s, in.camera, in.camera.forward());
  const double farError = perspectiveAliasing(s, in.camera, 100.0 * in.camera.forward());
  EXPECT_NEAR(nearError / farError, 1.0, 1e-3);  // the fade moves n by ~1e-4
}

TEST(Aliasing, UniformIsEq82) {
  const ShadowInput in = perpendicularCase(1.0, 100.0);
  const ShadowSetup s = computeShadowSetup(in, ShadowMethod::Uniform);
  // Exact but for the float32 margin finish() takes off the map (diagnostics.floatShrink).
  const double margin = 2.0 * s.diagnostics.floatShrink + 1e-9;
  for (double z : {1.0, 10.0, 100.0})
    EXPECT_NEAR(perspectiveAliasing(s, in.camera, z * in.camera.forward()) / (99.0 / z), 1.0, margin) << z;
}

TEST(Aliasing, ClassicNumbersAtARatioOfOneHundred) {
  // Light ⟂ view, z_f/z_n = 100: uniform max ≈ 99, LiSPSM ≈ 9.9, the logarithmic floor ≈ 4.6.
  const ShadowInput in = perpendicularCase(1.0, 100.0);
  const AliasingReport uniform = analyseAliasing(in, computeShadowSetup(in, ShadowMethod::Uniform));
  const AliasingReport lispsm = analyseAliasing(in, computeShadowSetup(in, ShadowMethod::Lispsm));
  EXPECT_NEAR(uniform.perspective.max / 99.0, 1.0, 0.02);
  EXPECT_NEAR(lispsm.perspective.max / 9.9, 1.0, 0.02);
  EXPECT_NEAR(lispsm.floor / std::log(100.0), 1.0, 0.02);
  EXPECT_GT(uniform.perspective.samples, 1000);
  // Relative → pixels: H / (2 tan(fovy/2)) pixels per tangent unit, R texels per map.
  EXPECT_NEAR(uniform.perspectivePixels.max, uniform.perspective.max * 720.0 / (2.0 * std::tan(glm::radians(30.0))) / 2048.0,
              1e-9 * uniform.perspectivePixels.max);
  // The storage factor and the surface figures exist for level ground under a noon sun.
  EXPECT_GT(uniform.surfacePixels.samples, 0);
  EXPECT_GT(uniform.storageFactor, lispsm.storageFactor);
}

// Smallest angle between the light's line and the rays through V's four corners and its centre.
double smallestAngleToLight(const Camera& c, const dvec3& l) {
  const double ty = std::tan(0.5 * c.fovy), tx = ty * c.aspect;
  double smallest = 90.0;
  for (int sx = -1; sx <= 1; ++sx)
    for (int sy = -1; sy <= 1; ++sy) {
      if (sx * sy == 0 && sx + sy != 0) continue;
      const dvec3 ray = glm::normalize(c.forward() + sx * tx * c.right() + sy * ty * c.up());
      smallest = std::min(smallest, glm::degrees(std::acos(std::min(1.0, std::abs(glm::dot(ray, glm::normalize(l)))))));
    }
  return smallest;
}

TEST(Aliasing, LispsmNeverWorseThanUniformFromThirtyDegrees) {
  // Random cameras inside S, z_f/z_n from 10 to 10⁴, fov 60°, aspect 4:3, with all of V at least
  // 30° off the light's line (γ ≥ 30° for the view direction alone is not enough: when a frustum
  // edge comes within ~20° of the light, B extends behind the eye along the warp axis and LiSPSM
  // — the thesis' §9.2 construction — loses up to 2.4× to uniform; measured 13 of 900 cases with
  // the view at 30°–35°). Then LiSPSM's max ≤ uniform's, and against the floor ln(z1/z0):
  // uniform ≥ the floor (nothing beats the ideal parameterization). How close LiSPSM comes to
  // eq. 8.9's √(z1/z0) off 90° is printed (last measured 2.12·√(z1/z0)); the bound itself is
  // derived and checked at 90° (LispsmMaxAliasingAtNinetyDegreesIsBoundedByEq89).
  SplitMix64 random(7);
  int checked = 0;
  double worstFactor = 0.0;
  for (int i = 0; i < 400; ++i) {
    ShadowInput in = perpendicularCase(random.logUniform(0.05, 2.0), 0.0);
    in.camera.far = in.camera.near * random.logUniform(10.0, 1e4);
    in.camera.yaw = random.uniform(0.0, 6.283);
    in.camera.pitch = glm::radians(random.uniform(-60.0, 60.0));
    const double elevation = glm::radians(random.uniform(10.0, 90.0)), azimuth = random.uniform(0.0, 6.283);
    in.sunDirection = {std::cos(elevation) * std::cos(azimuth), -std::sin(elevation), std::cos(elevation) * std::sin(azimuth)};
    if (smallestAngleToLight(in.camera, in.sunDirection) < 30.0) continue;
    const ShadowSetup lispsmSetup = computeShadowSetup(in, ShadowMethod::Lispsm);
    AliasingOptions options;
    options.raysPerAxis = 8;
    options.depthsPerRay = 24;
    const AliasingReport uniform = analyseAliasing(in, computeShadowSetup(in, ShadowMethod::Uniform), options);
    const AliasingReport lispsm = analyseAliasing(in, lispsmSetup, options);
    const double ratio = lispsmSetup.diagnostics.z1 / lispsmSetup.diagnostics.z0;
    const std::string where = "case " + std::to_string(i);
    EXPECT_LE(lispsm.perspective.max, uniform.perspective.max * (1.0 + 1e-9)) << where;
    EXPECT_GE(uniform.perspective.max, uniform.floor) << where;
    worstFactor = std::max(worstFactor, lispsm.perspective.max / std::sqrt(ratio));
    ++checked;
  }
  EXPECT_GT(checked, 100);
  std::printf("LiSPSM max / sqrt(z1/z0): worst %.3f over %d cases\n", worstFactor, checked);
}

// View ⟂ light (noon sun, level view, V ⊂ S): the warp axis is the view direction, so every
// sample's warp coordinate is its eye depth z less z_n, and along the view the map advances at
// least as fast as its warp coordinate does (the other map axis only adds to |J·v|): every
// sample's perspective aliasing is at most eq. 8.9 at its depth, with the n actually used —
// eq. 8.10's n_opt = z_n + √(z_n z_f), faded by the documented cap to 1/(1/n_opt − 1/(cap·d)).
// Its largest value on [z_n, z_f] is at an end (eq. 8.9 is convex in z): ≈ √(z_f/z_n) − √(z_n/z_f).
TEST(Aliasing, LispsmMaxAliasingAtNinetyDegreesIsBoundedByEq89) {
  SplitMix64 random(11);
  for (int i = 0; i < 100; ++i) {
    const double near = random.logUniform(0.05, 2.0);
    ShadowInput in = perpendicularCase(near, near * random.logUniform(10.0, 1e4));
    in.camera.yaw = random.uniform(0.0, 6.283);
    const double far = in.camera.far, d = far - near;
    const double nOpt = near + std::sqrt(near * far);
    const double n = 1.0 / (1.0 / nOpt - 1.0 / (kLispsmCapFactor * d));
    const double bound = std::max(eq89(near, near, far, n), eq89(far, near, far, n));
    AliasingOptions options;
    options.raysPerAxis = 8;
    options.depthsPerRay = 24;
    const ShadowSetup setup = computeShadowSetup(in, ShadowMethod::Lispsm);
    const AliasingReport lispsm = analyseAliasing(in, setup, options);
    ASSERT_GT(lispsm.perspective.samples, 1000);
    // finish() may give up a sliver of the map to float32 (floatShrink): texels that much larger.
    EXPECT_LE(lispsm.perspective.max, bound / (1.0 - setup.diagnostics.floatShrink) * (1.0 + 1e-9)) << "z_f/z_n " << far / near;
    EXPECT_LE(bound, std::sqrt(far / near));  // the √ law: (z_f − z_n)/√(z_n z_f) < √(z_f/z_n)
  }
}

}  // namespace
}  // namespace forest::shadows
