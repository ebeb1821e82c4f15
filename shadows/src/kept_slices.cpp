#include "forest/shadows/kept_slices.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <utility>

#include "forest/shadows/casters.hpp"
#include "forest/shadows/focus_body.hpp"
#include "light_space.hpp"
#include "shadow_methods.hpp"

namespace forest::shadows {
namespace {

using glm::dvec2;
using glm::dvec3;
using glm::dvec4;

// The Jacobian of (u, v) across the light → the map's (x, y) at p, or nothing where the map
// cannot place p (w ≤ 0) or the Jacobian is not finite.
std::optional<glm::dmat2> mapJacobian(const ShadowSetup& setup, const dvec3& p, const dvec3& u, const dvec3& v) {
  const dvec4 h = setup.worldToShadowClip * dvec4(p, 1.0);
  if (!(h.w > 0.0)) return std::nullopt;
  auto column = [&](const dvec3& d) {
    const dvec4 e = setup.worldToShadowClip * dvec4(d, 0.0);
    return (dvec2(e) * h.w - dvec2(h) * e.w) / (h.w * h.w);
  };
  const glm::dmat2 j(column(u), column(v));
  if (!std::isfinite(j[0][0] + j[0][1] + j[1][0] + j[1][1])) return std::nullopt;
  return j;
}

// |det| of that Jacobian: map area per world area (0 where it does not exist).
double mapAreaPerWorldArea(const ShadowSetup& setup, const dvec3& p, const dvec3& u, const dvec3& v) {
  const std::optional<glm::dmat2> j = mapJacobian(setup, p, u, v);
  return j ? std::abs(glm::determinant(*j)) : 0.0;
}

// The largest singular value of a 2 × 2 matrix: √ of the largest eigenvalue of JᵀJ (closed form).
double largestSingularValue(const glm::dmat2& j) {
  const glm::dmat2 g = glm::transpose(j) * j;
  const double mean = 0.5 * (g[0][0] + g[1][1]), half = 0.5 * (g[0][0] - g[1][1]);
  return std::sqrt(mean + std::sqrt(half * half + g[1][0] * g[1][0]));
}

// A fit places B's outermost vertices on its border exactly (in double): a millionth of the map's
// width covers the rounding.
constexpr double kBorderTolerance = 1e-6;

// Every vertex of B inside the map with its filter border (in double, as the fit places it) and
// inside [−1, 1]³ as the GPU computes it from this frame's eye (mapCoordinateBound; tsm's linear
// depth row likewise), as computeShadowSetup guarantees for a fresh fit.
bool holdsBody(const ShadowSetup& kept, const ShadowSetup& fresh, const ShadowInput& in) {
  const double inside = 1.0 - clipBorder(in) + kBorderTolerance;
  constexpr double gamma4 = 4.0 * kFloatUnitRoundoff / (1.0 - 4.0 * kFloatUnitRoundoff);
  for (const dvec3& p : fresh.body.vertices()) {
    const dvec3 exact = shadowMapCoordinates(kept, p);
    if (!(std::abs(exact.x) <= inside && std::abs(exact.y) <= inside)) return false;
    const dvec3 bound = mapCoordinateBound(kept.eyeRelativeToShadowClipF, p - in.camera.position);
    if (!(bound.x <= 1.0 && bound.y <= 1.0)) return false;
    if (kept.linearDepth) {
      const dvec4 row(kept.eyeRelativeToLightDepthF), q(dvec3(glm::vec3(p - in.camera.position)), 1.0);
      if (!(std::abs(glm::dot(row, q)) + gamma4 * glm::dot(glm::abs(row), glm::abs(q)) <= 1.0)) return false;
    } else if (!(bound.z <= 1.0)) {
      return false;
    }
  }
  return true;
}

// The part of the slice that can be seen: V ∩ S ∩ R from the nearest visible depth on.
std::pmr::vector<dvec3> visibleVertices(const ShadowInput& in) {
  Camera camera = in.camera;
  if (in.nNear && *in.nNear > camera.near && *in.nNear < camera.far) camera.near = *in.nNear;
  ConvexBody visible = viewFrustumBody(camera);
  visible.clip(in.scene);
  if (in.receivers) visible.clip(*in.receivers);
  return visible.vertices();
}

}  // namespace

bool holdsStillByItself(ShadowMethod method) { return methodUnit(method).holdsStillByItself; }

Camera extrapolatedCamera(const Camera& camera, const Camera& last, double frames) {
  Camera ahead = camera;
  ahead.position += frames * (camera.position - last.position);
  const double turn = std::remainder(camera.yaw - last.yaw, 2.0 * std::numbers::pi);
  ahead.yaw += frames * turn;
  ahead.pitch = std::clamp(camera.pitch + frames * (camera.pitch - last.pitch), -0.5 * std::numbers::pi, 0.5 * std::numbers::pi);
  return ahead;
}

double texelSideRatio(const ShadowSetup& a, const ShadowSetup& b, std::span<const dvec3> points, const dvec3& l) {
  const auto [u, v] = axesAcrossLight(glm::normalize(l));
  double worst = 0.0;
  for (const dvec3& p : points) {
    const double areaB = mapAreaPerWorldArea(b, p, u, v);
    if (!(areaB > 0.0)) continue;
    const double areaA = mapAreaPerWorldArea(a, p, u, v);
    if (!(areaA > 0.0)) return std::numeric_limits<double>::infinity();
    worst = std::max(worst, std::sqrt(areaB / areaA));  // texel side ∝ 1 / √(map area per world area)
  }
  return worst;
}

double finestTexelSide(const ShadowSetup& setup, int mapSize, std::span<const dvec3> points, const dvec3& l) {
  const auto [u, v] = axesAcrossLight(glm::normalize(l));
  const double texel = 2.0 / mapSize;
  double finest = std::numeric_limits<double>::infinity();
  for (const dvec3& p : points)
    if (const std::optional<glm::dmat2> j = mapJacobian(setup, p, u, v)) finest = std::min(finest, texel / largestSingularValue(*j));
  return finest;
}

std::string_view KeptSlices::whyRefit(const Kept& kept, const ShadowInput& in, ShadowMethod method, const ShadowSetup& fresh,
                                      std::span<const dvec3> visible, const KeepLimits& limits) const {
  if (!kept.valid) return "first";
  if (kept.method != method || kept.mapSize != in.mapSize || kept.borderTexels != in.borderTexels) return "method";
  if (angleDeg(kept.sun, in.sunDirection) > limits.sunDeg) return "sun";
  if (!holdsBody(kept.setup, fresh, in)) return "outside";
  if (texelSideRatio(kept.setup, fresh, visible, in.sunDirection) > limits.texelGrowth) return "texels";
  return "";
}

std::optional<ShadowSetup> KeptSlices::refit(const ShadowInput& input, ShadowMethod method, const ShadowSetup& fresh,
                                              std::span<const dvec3> visible, const KeepLimits& limits, const Camera& last) {
  ShadowInput snapped = input;
  snapped.snapWarp = true;
  snapped.carried = 0.0;
  snapped.borderTexels = input.borderTexels + static_cast<int>(std::ceil(limits.slackShare * input.mapSize));
  // Depth costs no texels: B's vertices moved along the light and against it by the slack's share
  // of B's extent along the light.
  const dvec3 l = glm::normalize(input.sunDirection);
  const auto bodyVertices = fresh.body.vertices();
  double nearest = std::numeric_limits<double>::infinity(), farthest = -nearest;
  for (const dvec3& v : bodyVertices) {
    nearest = std::min(nearest, glm::dot(v, l));
    farthest = std::max(farthest, glm::dot(v, l));
  }
  const double depthSlack = limits.slackShare * (farthest - nearest);
  alsoCover_.clear();
  for (const dvec3& v : bodyVertices) {
    alsoCover_.push_back(v + depthSlack * l);
    alsoCover_.push_back(v - depthSlack * l);
  }
  const std::size_t slackPoints = alsoCover_.size();
  for (int frames = std::max(limits.horizonFrames, 1);; frames /= 2) {
    alsoCover_.resize(slackPoints);  // and B of the camera `frames` ahead
    const Camera ahead = extrapolatedCamera(input.camera, last, frames);
    const ConvexBody body = computeFocusBody(ahead, input.sunDirection, input.scene, input.receivers);
    for (const dvec3& v : body.vertices()) alsoCover_.push_back(v);
    snapped.alsoCover = alsoCover_;
    ShadowSetup setup = computeShadowSetup(snapped, method);
    rebaseToEye(setup, input.camera.position);
    // The map holds this frame's B but in degenerate cases (a float32 fallback), where the fresh
    // fit serves this frame.
    if (!setup.empty && holdsBody(setup, fresh, input) && texelSideRatio(setup, fresh, visible, input.sunDirection) <= limits.texelGrowth)
      return setup;
    if (frames == 1) return std::nullopt;
  }
}

ShadowSetup KeptSlices::setup(const ShadowInput& input, ShadowMethod method, int slice, const KeepLimits& limits, SliceKeeping& keeping) {
  Kept& kept = kept_.at(static_cast<size_t>(slice));
  const std::optional<Camera> lastFrame = std::exchange(lastCamera_.at(static_cast<size_t>(slice)), input.camera);
  keeping = SliceKeeping{};
  if (holdsStillByItself(method)) {  // a method stable by construction: as without keeping
    keeping.refit = "stable";
    kept.valid = false;
    return computeShadowSetup(input, method);
  }
  ShadowInput unsmoothed = input;
  unsmoothed.carried = 0.0;  // the fresh fit to compare with: eq. 8.13's n of this frame
  ShadowSetup fresh = computeShadowSetup(unsmoothed, method);
  if (fresh.empty) {  // nothing to keep a map for
    keeping.refit = "empty";
    kept.valid = false;
    return computeShadowSetup(input, method);
  }
  if (!lastFrame) {
    // A first frame (or after a cut): nothing to extrapolate, and a frame alone gains nothing from
    // a margin — the fresh fit, as without keeping, kept for the next frame to test.
    keeping.refit = "first";
    kept = Kept{true, fresh, method, input.sunDirection, input.mapSize, input.borderTexels, 0};
    return fresh;
  }
  const auto visible = visibleVertices(input);
  keeping.refit = whyRefit(kept, input, method, fresh, visible, limits);
  ShadowSetup setup;
  if (keeping.refit.empty()) {
    setup = kept.setup;
    rebaseToEye(setup, input.camera.position);
    keeping.kept = true;
    keeping.keptFrames = ++kept.frames;
  } else if (std::optional<ShadowSetup> refitted = refit(input, method, fresh, visible, limits, *lastFrame)) {
    kept = Kept{true, *refitted, method, input.sunDirection, input.mapSize, input.borderTexels, 0};
    setup = std::move(*refitted);
  } else {
    kept.valid = false;  // no margin within the texel limit: the fresh fit, and a refit next frame
    return computeShadowSetup(input, method);
  }
  setup.body = std::move(fresh.body);  // this frame's B (inside the map: holdsBody)
  return setup;
}

void KeptSlices::reset() {
  for (Kept& k : kept_) k = Kept{};
  lastCamera_.fill(std::nullopt);
}

}  // namespace forest::shadows
