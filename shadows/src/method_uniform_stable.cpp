// uniform-stable: an orthographic map whose orientation is fixed in the world and whose size comes
// from the view's bounding sphere, its origin snapped to whole texels (stabilised cascades,
// DESIGN §12): shadows do not swim when the camera turns or moves. Carries its map radius from
// frame to frame (stableMapRadius: steps with hysteresis).
#include <algorithm>
#include <cmath>

#include "forest/shadows/focus_body.hpp"
#include "light_space.hpp"
#include "shadow_methods.hpp"

namespace forest::shadows {

using glm::dmat4;
using glm::dvec3;

double stableMapRadius(double sphereRadius, std::optional<double> previous) {
  if (!(sphereRadius > 0.0) || !std::isfinite(sphereRadius)) return sphereRadius;
  if (previous && *previous >= sphereRadius && *previous <= kStableRadiusHysteresis * sphereRadius) return *previous;
  return std::exp2(std::ceil(std::log2(sphereRadius) / kStableRadiusStep) * kStableRadiusStep);
}

void setupUniformStable(const FocusedView& view, ShadowSetup& setup) {
  const ShadowInput& in = view.in;
  const Camera& camera = in.camera;
  // World-fixed in-plane axes (the world axis least parallel to the light), extent from V's
  // bounding sphere (independent of the camera's rotation), its radius quantised to steps with
  // hysteresis (stableMapRadius), origin snapped to texels.
  const dvec3 axis = std::abs(view.l.z) < 0.9 ? dvec3(0, 0, 1) : dvec3(1, 0, 0);
  const dmat4 frame = computeLightFrame(-view.l, axis, camera, dvec3(0.0));
  const ConvexBody frustum = viewFrustumBody(camera);
  const auto corners = frustum.vertices();
  dvec3 centre(0.0);
  for (const dvec3& p : corners) centre += p;
  centre /= static_cast<double>(corners.size());
  double sphere = 0.0;
  for (const dvec3& p : corners) sphere = std::max(sphere, glm::distance(p, centre));
  const std::optional<double> previous = in.carried > 0.0 ? std::optional<double>(in.carried) : std::nullopt;
  const double radius = stableMapRadius(sphere, previous);
  setup.diagnostics.stableRadius = radius;
  const dmat4 toMap = computeWarp(0.0, dvec3(0.0), 0.0) * frame;
  const dvec3 centreMap = transformPoint(toMap, centre);
  // mapSize texels of equal size cover the sphere's square plus one texel of snapping slack
  // plus the filter border on each side; the map's origin sits on a whole texel.
  const double texel = 2.0 * radius / (in.mapSize - 1 - 2 * in.borderTexels);
  Aabb box = boundsIn(toMap, view.bodyVertices);
  for (int a = 0; a < 2; ++a) {
    box.min[a] = (std::floor((centreMap[a] - radius) / texel) - in.borderTexels) * texel;
    box.max[a] = box.min[a] + in.mapSize * texel;
  }
  setup.worldToShadowClip = fitToUnitCube(box, 0.0) * toMap;
}

double carryStableRadius(const ShadowSetup& setup) { return setup.diagnostics.stableRadius; }

}  // namespace forest::shadows
