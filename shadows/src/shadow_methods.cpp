#include "shadow_methods.hpp"

#include <array>

#include "forest/core/error.hpp"
#include "forest/shadows/focus_body.hpp"
#include "light_space.hpp"

namespace forest::shadows {
namespace {

// One row per method, in the enum's order.
constexpr std::array<ShadowMethodUnit, 5> kMethods{{
    {ShadowMethod::Uniform, setupUniform, carryNothing, "uniform cannot keep B inside its map in float32", true, false},
    {ShadowMethod::UniformStable, setupUniformStable, carryStableRadius,
     "uniform-stable cannot keep B inside its map in float32: uniform", true, true},
    {ShadowMethod::Lispsm, setupLispsm, carryLispsmN, "lispsm cannot keep B inside its map in float32: uniform", true, false},
    {ShadowMethod::Tsm, setupTsm, carryNothing, "tsm cannot keep B inside its map in float32: uniform", true, false},
    {ShadowMethod::TsmIterative, setupTsmIterative, carryNothing, "tsm-iterative cannot keep B inside its map in float32: uniform",
     false, false},
}};

}  // namespace

const ShadowMethodUnit& methodUnit(ShadowMethod method) {
  for (const ShadowMethodUnit& unit : kMethods)
    if (unit.method == method) return unit;
  throw Error("shadows: a shadow method without a row in the method table");
}

std::vector<ShadowMethod> comparedShadowMethods() {
  std::vector<ShadowMethod> methods;
  for (const ShadowMethodUnit& unit : kMethods)
    if (unit.compared) methods.push_back(unit.method);
  return methods;
}

double carriedToNextFrame(ShadowMethod method, const ShadowSetup& setup) { return methodUnit(method).carry(setup); }

FittedView fitView(const FocusedView& view) {
  const Camera& camera = view.in.camera;
  FittedView fitted{viewFrustumBody(camera), std::pmr::vector<glm::dvec3>(convexBodyMemory()), glm::dmat4(1.0)};
  fitted.visible.clip(view.in.scene);
  if (view.in.receivers) fitted.visible.clip(*view.in.receivers);
  fitted.fitVertices.assign(view.bodyVertices.begin(), view.bodyVertices.end());
  for (const glm::dvec3& v : fitted.visible.vertices()) fitted.fitVertices.push_back(v);
  fitted.fitVertices.insert(fitted.fitVertices.end(), view.in.alsoCover.begin(), view.in.alsoCover.end());
  fitted.lightFrame = computeLightFrame(-view.l, view.bodyVector, camera, camera.position);
  return fitted;
}

}  // namespace forest::shadows
