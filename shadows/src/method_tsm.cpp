// tsm, tsm-iterative: the trapezoidal shadow map (Martin & Tan 2004). The uniform map's plane
// warped so that a trapezoid around B's footprint fills it (§6, trapezoid.hpp), the 80% rule for
// the focus region, or its iterative variant (§6.2); depth stays the uniform map's linear light
// depth (§4). Carries nothing from frame to frame.
#include <algorithm>
#include <optional>
#include <span>

#include "light_space.hpp"
#include "shadow_methods.hpp"
#include "trapezoid.hpp"

namespace forest::shadows {
namespace {

using glm::dmat4;
using glm::dvec3;

// TSM (Martin & Tan 2004): L is the uniform map fitted to B without a border (the light's
// post-perspective space of §3, orthographic for the sun); the trapezoid of §6 around B's
// footprint in L's plane, N_T applied to x, y and w only, the filter border kept after N_T; depth
// stays L's linear z (§4).
void computeTsm(const FocusedView& view, bool iterative, ShadowSetup& setup) {
  const ShadowInput& in = view.in;
  const Camera& camera = in.camera;
  const FittedView fitted = fitView(view);
  const std::span<const dvec3> bodyVertices = fitted.fitVertices;
  const ConvexBody& visible = fitted.visibleOr(setup.body);
  const dmat4& lightFrame = fitted.lightFrame;
  const dmat4 L = fitUniform(lightFrame, bodyVertices, 0.0);
  auto plane = [&](const dvec3& p) { return glm::dvec2(transformPoint(L, p)); };
  TrapezoidInput t;
  for (const dvec3& p : bodyVertices) t.footprint.push_back(plane(p));
  t.eye = plane(camera.position);
  const auto visibleVertices = visible.vertices();
  dvec3 centre(0.0);
  double nearest = kInfinity, farthest = -kInfinity;
  for (const dvec3& p : visibleVertices) {
    centre += p;
    const double depth = glm::dot(p - camera.position, camera.forward());
    nearest = std::min(nearest, depth);
    farthest = std::max(farthest, depth);
  }
  t.centre = plane(centre / static_cast<double>(visibleVertices.size()));
  // §6.4: the focus region is the first focusShare of the depth range the visible part spans.
  t.focusPoint = plane(camera.position + camera.forward() * (nearest + in.tsmFocusShare * (farthest - nearest)));
  t.iterative = iterative;
  t.mapLines = in.mapSize;

  setup.linearDepth = true;
  setup.worldToLightDepth = glm::dvec4(L[0][2], L[1][2], L[2][2], L[3][2]);  // L's z row
  const std::optional<Trapezoid> trapezoid = computeTrapezoid(t, setup.diagnostics.fallback);
  // (x_T·w, y_T·w, w) from L's (x, y, 1), the border kept free after N_T; clip z = 0 (the depth
  // is the linear row above). Without a trapezoid: L itself with the border.
  glm::dmat3 n(1.0);
  if (trapezoid) {
    n = trapezoid->toSquare;
    ShadowDiagnostics& d = setup.diagnostics;
    d.tsmLambda = trapezoid->lambda;
    d.tsmFocus = trapezoid->focus;
    d.tsmEta = trapezoid->eta;
    d.tsmXi = trapezoid->xi;
    d.tsmFocusArea = trapezoid->focusArea;
  }
  const double keep = 1.0 - clipBorder(in);
  dmat4 nt(0.0);
  for (int c = 0; c < 3; ++c) {
    const int column = c < 2 ? c : 3;  // L's x, y and the constant
    nt[column][0] = keep * n[c][0];
    nt[column][1] = keep * n[c][1];
    nt[column][3] = n[c][2];
  }
  setup.worldToShadowClip = nt * L;
}

}  // namespace

void setupTsm(const FocusedView& view, ShadowSetup& setup) { computeTsm(view, false, setup); }
void setupTsmIterative(const FocusedView& view, ShadowSetup& setup) { computeTsm(view, true, setup); }

}  // namespace forest::shadows
