// lispsm: the light space perspective shadow map, thesis §9.2 step by step — the light frame L
// (§9.2.3), B in L and the warp axis (§9.2.4), n from eq. 8.13 (§9.2.5, the misprint fixed:
// lispsmNearDistance), faded to the uniform map at the cap (§8.3), the warp P and the fit.
// Carries n from frame to frame: n moves kNearDistanceSmoothing of the way to this frame's value.
#include <algorithm>
#include <cmath>

#include "forest/shadows/focus_body.hpp"
#include "light_space.hpp"
#include "shadow_methods.hpp"

namespace forest::shadows {
namespace {

using glm::dmat4;
using glm::dvec3;

// B is flat across the light when its depth along the warp axis is below this share of its size.
constexpr double kFlatShare = 1e-12;

// §9.2.5: the box n is computed on — B in light space, or the body of the virtual frustum whose
// far is n_far and near n_near (ShadowInput::nFar, nNear).
Aabb nBoxOf(const ShadowInput& in, const glm::dvec3& l, const dmat4& lightFrame, const Aabb& bLs) {
  const Camera& camera = in.camera;
  Camera virtualCamera = camera;
  if (in.nFar && *in.nFar != camera.far) virtualCamera.far = *in.nFar;
  if (in.nNear && *in.nNear > camera.near && *in.nNear < 0.999 * virtualCamera.far) virtualCamera.near = *in.nNear;
  if (virtualCamera.near != camera.near || virtualCamera.far != camera.far) {
    const ConvexBody virtualBody = computeFocusBody(virtualCamera, l, in.scene, in.receivers);
    if (!virtualBody.empty()) return boundsIn(lightFrame, virtualBody.vertices());
  }
  return bLs;
}

}  // namespace

double lispsmNearDistance(double d, double z0, double z1) {
  const double ratio = z1 / z0;
  if (!(ratio > 1.0) || !std::isfinite(ratio)) return kInfinity;
  return d / (std::sqrt(ratio) - 1.0);
}

void setupLispsm(const FocusedView& view, ShadowSetup& setup) {
  const ShadowInput& in = view.in;
  const Camera& camera = in.camera;
  const FittedView fitted = fitView(view);
  const dmat4& lightFrame = fitted.lightFrame;

  // §9.2.4: B in light space; the warp runs along −z from B_znear to B_zfar.
  const Aabb bLs = boundsIn(lightFrame, view.bodyVertices);
  const dvec3 eWorld = computeNearPoint(fitted.visibleOr(setup.body), camera);
  const dvec3 eLs = transformPoint(lightFrame, eWorld);

  // §9.2.5: n from eq. 8.13, on B or on the body of the virtual frustum (far = n_far, near = n_near).
  const Aabb nBox = nBoxOf(in, view.l, lightFrame, bLs);
  const double d = nBox.max.z - nBox.min.z;
  const auto [z0, z1] = computeZ0Z1(lightFrame, camera, eWorld, nBox.max.z, nBox.min.z);
  const double nOpt = lispsmNearDistance(d, z0, z1);
  ShadowDiagnostics& diag = setup.diagnostics;
  diag.z0 = z0;
  diag.z1 = z1;
  diag.d = d;
  // The cap scales with B's depth along the warp axis; a B flat across the light has none, and
  // then nothing to warp: the cap falls back to B's size.
  const double depthScale = std::max(d, bLs.max.z - bLs.min.z);
  const bool flatAcrossLight = !(depthScale > kFlatShare * bLs.diagonal());
  diag.nCap = kLispsmCapFactor * (flatAcrossLight ? bLs.diagonal() : depthScale);
  diag.nOptimal = flatAcrossLight || !(nOpt > 0.0) ? diag.nCap : std::min(nOpt, diag.nCap);
  double n = diag.nOptimal;
  const double previousN = in.carried;  // over time (kNearDistanceSmoothing)
  if (in.snapWarp) n = std::min(std::exp2(std::round(std::log2(n) / kWarpNStep) * kWarpNStep), diag.nCap);
  else if (previousN > 0.0 && std::isfinite(previousN)) n = std::min(previousN + kNearDistanceSmoothing * (diag.nOptimal - previousN), diag.nCap);
  diag.n = n;
  // Fade: the warp strength 1/n falls linearly to 0 as n reaches the cap.
  const double u = !flatAcrossLight && n > 0.0 ? std::max(0.0, 1.0 / n - 1.0 / diag.nCap) : 0.0;
  diag.warp = u;
  if (flatAcrossLight) diag.fallback = "B flat across the light: uniform";
  else if (u == 0.0) diag.fallback = "n at cap: uniform";

  // The warp starts at the light-space near end of what the map holds: B, and the points a kept
  // slice's refit adds (ShadowInput::alsoCover), so that every one of them has w ≥ 1.
  const double warpStart = in.alsoCover.empty() ? bLs.max.z : boundsIn(lightFrame, fitted.fitVertices).max.z;
  const dmat4 toMap = computeWarp(u, eLs, warpStart) * lightFrame;
  setup.worldToShadowClip = fitToUnitCube(boundsIn(toMap, fitted.fitVertices), clipBorder(in)) * toMap;
}

// The n this frame used, for the next frame's smoothing; none where the slice had nothing to shadow.
double carryLispsmN(const ShadowSetup& setup) { return setup.empty ? 0.0 : setup.diagnostics.n; }

}  // namespace forest::shadows
