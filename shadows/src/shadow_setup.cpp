#include "forest/shadows/shadow_setup.hpp"

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <span>
#include <string>

#include "forest/core/error.hpp"
#include "forest/shadows/casters.hpp"
#include "forest/shadows/focus_body.hpp"
#include "light_space.hpp"
#include "shadow_methods.hpp"

namespace forest::shadows {
namespace {

using glm::dmat4;
using glm::dvec3;
using glm::dvec4;

// Each shrink aims this far inside the bound: rounding the shrunk matrix to float32 moves the
// result again by up to ~u·Σ|m·p|, which a fixed 4u step chases for thousands of steps when B is
// thin (found with held-back seeds: 2e-8 per step); growing the margin 4× per attempt settles in a
// few, and the first attempt is the tightest.
double shrinkMargin(int attempt) { return 4.0 * kFloatUnitRoundoff * std::ldexp(1.0, 2 * attempt); }

// The float32 matrices, with B kept inside [−1, 1]³ as the GPU computes it: a fit exact in
// double can leave B's vertices outside by ~1e-3 after float32 rounding when B is 10⁴ times
// longer than wide (camera-relative positions of 1e5 m keep only ~6 mm). Each shadow-clip axis
// is shrunk about 0 until the worst case (float matrix, float positions, plus the bound on the
// GPU's rounding) is inside: see mapCoordinateBound. Nothing when no shrink does it (w may reach
// 0 on the float32 path): the caller falls back.
std::optional<ShadowSetup> finish(ShadowSetup setup, const dvec3& eye) {
  const auto vertices = setup.body.vertices();
  if (setup.linearDepth) {
    // The same for the linear depth row (tsm): shrink it about 0 until B's depth is inside
    // [−1, 1] as the GPU evaluates it in float32 (γ₄ bound, as in mapCoordinateBound).
    for (int attempt = 0;; ++attempt) {
      rebaseToEye(setup, eye);
      const glm::dvec4 rowF(setup.eyeRelativeToLightDepthF);
      double worst = 0.0;
      for (const dvec3& v : vertices) {
        const glm::dvec4 p(dvec3(glm::vec3(v - eye)), 1.0);
        const double exact = glm::dot(rowF, p), magnitude = glm::dot(glm::abs(rowF), glm::abs(p));
        worst = std::max(worst, std::abs(exact) + 4.0 * kFloatUnitRoundoff / (1.0 - 4.0 * kFloatUnitRoundoff) * magnitude);
      }
      if (worst <= 1.0) break;
      if (attempt == 8) return std::nullopt;
      setup.worldToLightDepth *= (1.0 - shrinkMargin(attempt)) / worst;
    }
  }
  for (int attempt = 0;; ++attempt) {
    rebaseToEye(setup, eye);
    dvec3 worst(0.0);
    for (const dvec3& v : vertices) worst = glm::max(worst, mapCoordinateBound(setup.eyeRelativeToShadowClipF, v - eye));
    if (worst.x <= 1.0 && worst.y <= 1.0 && worst.z <= 1.0) break;
    if (attempt == 8) return std::nullopt;
    for (int axis = 0; axis < 3; ++axis) {
      if (worst[axis] <= 1.0) continue;
      const double shrink = (1.0 - shrinkMargin(attempt)) / worst[axis];
      for (int c = 0; c < 4; ++c) setup.worldToShadowClip[c][axis] *= shrink;
      setup.diagnostics.floatShrink = std::max(setup.diagnostics.floatShrink, 1.0 - shrink);
    }
  }
  setup.worldToShadowClipF = glm::mat4(setup.worldToShadowClip);
  setup.diagnostics.bodyVertices = vertices.size();
  return setup;
}

}  // namespace

void rebaseToEye(ShadowSetup& setup, const dvec3& eye) {
  setup.eyeRelativeToShadowClipF = glm::mat4(setup.worldToShadowClip * glm::translate(dmat4(1.0), eye));
  const glm::dvec4& r = setup.worldToLightDepth;
  setup.eyeRelativeToLightDepthF = glm::vec4(dvec3(r), r.w + glm::dot(dvec3(r), eye));
}

dvec3 mapCoordinateBound(const glm::mat4& eyeRelativeToShadowClip, const dvec3& eyeRelativePosition) {
  // Rounding of a float dot product of 4 terms, in any order or with FMA: |error| ≤ γ₄ Σ|aᵢbᵢ|,
  // γ₄ = 4u / (1 − 4u) (Higham, Accuracy and Stability, §3.1); the divide by w adds u.
  constexpr double u = kFloatUnitRoundoff, gamma4 = 4.0 * u / (1.0 - 4.0 * u);
  const glm::dvec4 p(glm::dvec3(glm::vec3(eyeRelativePosition)), 1.0);  // what the GPU gets
  const glm::dmat4 m(eyeRelativeToShadowClip);
  glm::dvec4 h(0.0), magnitude(0.0);
  for (int c = 0; c < 4; ++c) {
    h += m[c] * p[c];
    magnitude += glm::abs(m[c] * p[c]);
  }
  const glm::dvec4 error = gamma4 * magnitude;
  const double w = h.w - error.w;
  if (!(w > 0.0)) return dvec3(kInfinity);
  dvec3 bound;
  for (int i = 0; i < 3; ++i) bound[i] = ((std::abs(h[i]) + error[i]) / w) * (1.0 + u);
  return bound;
}

dvec3 shadowMapCoordinates(const ShadowSetup& setup, const dvec3& world) {
  const dvec4 h = setup.worldToShadowClip * dvec4(world, 1.0);
  const double depth = setup.linearDepth ? glm::dot(setup.worldToLightDepth, dvec4(world, 1.0)) : h.z / h.w;
  return dvec3(h.x / h.w, h.y / h.w, depth);
}

void validateShadowInput(const ShadowInput& in) {
  const Camera& c = in.camera;
  const double sun = glm::length(in.sunDirection);
  if (!std::isfinite(sun) || sun < 1e-300) throw InputError("sun_dir: expected a finite non-zero vector");
  for (double v : {c.position.x, c.position.y, c.position.z, c.yaw, c.pitch, c.roll, c.fovy, c.aspect, c.near, c.far}) {
    if (!std::isfinite(v)) throw InputError("camera: values must be finite");
  }
  if (!(c.near > 0.0) || !(c.far > c.near)) throw InputError("camera: expected 0 < near < far");
  if (!(c.fovy > 0.0) || !(c.fovy < std::numbers::pi)) throw InputError("camera: expected 0 < fovy < 180°");
  if (!(c.aspect > 0.0)) throw InputError("camera: expected aspect > 0");
  if (!in.scene.valid() || !std::isfinite(in.scene.diagonal())) throw InputError("scene box: expected finite min <= max");
  if (in.nFar && !(*in.nFar > c.near)) throw InputError("n_far: expected a distance greater than near");
  if (in.nNear && !std::isfinite(*in.nNear)) throw InputError("n_near: expected a finite distance");
  if (const std::optional<std::string> outside = outsideShadowDomain(in)) throw InputError(*outside);
  if (in.mapSize < 16 || in.mapSize > kMaxMapSize)
    throw InputError(fmt::format("map size {}: expected 16 to {} texels", in.mapSize, kMaxMapSize));
  if (in.borderTexels < 0 || 4 * in.borderTexels >= in.mapSize)
    throw InputError(fmt::format("border {} texels: expected 0 to a quarter of the map size", in.borderTexels));
}

namespace {

// ShadowInput::snapWarp: the body vector's azimuth about the light rounded to kWarpRotationStepDeg
// (its part along the light kept). One nearly parallel to the light has no azimuth to round.
dvec3 snappedAboutLight(const dvec3& bodyVector, const dvec3& l) {
  const auto [u, v] = axesAcrossLight(l);
  const double a = glm::dot(bodyVector, u), b = glm::dot(bodyVector, v), across = std::hypot(a, b);
  if (!(across > 1e-6)) return bodyVector;
  const double step = glm::radians(kWarpRotationStepDeg);
  const double azimuth = std::round(std::atan2(b, a) / step) * step;
  return across * (std::cos(azimuth) * u + std::sin(azimuth) * v) + glm::dot(bodyVector, l) * l;
}

// One method's setup (shadow_methods.hpp) between the steps every method shares: B, the body
// vector and γ before; the float32 check after. Nothing when float32 cannot keep B inside its map.
std::optional<ShadowSetup> computeMethodSetup(const ShadowInput& in, ShadowMethod method) {
  const Camera& camera = in.camera;
  const dvec3 l = glm::normalize(in.sunDirection);
  ShadowSetup setup;
  setup.body = computeFocusBody(camera, l, in.scene, in.receivers);
  if (setup.body.empty()) {
    setup.diagnostics.fallback = "empty focus body";
    return finish(setup, camera.position);
  }
  setup.empty = false;
  const auto bodyVertices = setup.body.vertices();
  dvec3 bodyVector = computeBodyVector(bodyVertices, camera);
  if (in.snapWarp) bodyVector = snappedAboutLight(bodyVector, l);
  const FocusedView view{in, l, bodyVertices, bodyVector};
  setup.diagnostics.gammaDeg = angleDeg(view.bodyVector, l);
  methodUnit(method).setup(view, setup);
  return finish(setup, camera.position);
}

}  // namespace

std::optional<std::string> outsideShadowDomain(const ShadowInput& in) {
  const Camera& c = in.camera;
  const double distance = glm::length(c.position);
  if (!(c.far - c.near >= kMinViewDepthShare * distance))
    return fmt::format("camera: a view {:.3g} m deep (far - near) at {:.3g} m from the world origin is outside the "
                       "float32 domain: it must be at least 2^-23 = {:.3g} of that distance deep ({:.3g} m)",
                       c.far - c.near, distance, kMinViewDepthShare, kMinViewDepthShare * distance);
  return std::nullopt;
}

ShadowSetup computeShadowSetup(const ShadowInput& in, ShadowMethod method) {
  validateShadowInput(in);
  if (std::optional<ShadowSetup> setup = computeMethodSetup(in, method)) return *setup;
  // Float32 cannot keep B inside this method's map (w reaches 0 on the GPU's path): the focused
  // uniform map, whose w is 1; failing that, no shadows this time. Never an exception out of a
  // frame.
  if (method != ShadowMethod::Uniform) {
    if (std::optional<ShadowSetup> setup = computeMethodSetup(in, ShadowMethod::Uniform)) {
      setup->diagnostics.fallback = methodUnit(method).float32FallbackNote;
      return *setup;
    }
  }
  ShadowSetup none;
  none.body = computeFocusBody(in.camera, glm::normalize(in.sunDirection), in.scene, in.receivers);
  none.diagnostics.fallback = "no map keeps B inside it in float32: no shadows";
  none.eyeRelativeToShadowClipF = glm::mat4(none.worldToShadowClip * glm::translate(dmat4(1.0), in.camera.position));
  none.worldToShadowClipF = glm::mat4(none.worldToShadowClip);
  return none;
}

}  // namespace forest::shadows
