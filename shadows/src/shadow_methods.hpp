#pragma once
// The shadow methods as units (module-internal): one file each (method_*.cpp), one row each in
// the table of shadow_methods.cpp. computeShadowSetup (shadow_setup.cpp) does what they share —
// validate, the focus body B, the body vector, the float32 check and fallback — and calls the
// row's setup in between. A new method: its enum value and name (shadow_setup.hpp), its file, its
// row.
#include <glm/glm.hpp>

#include <memory_resource>
#include <span>
#include <string_view>
#include <vector>

#include "forest/core/convex_body.hpp"
#include "forest/shadows/shadow_setup.hpp"

namespace forest::shadows {

// What every method starts from: the input, the unit light direction, B's vertices (B itself is
// in the setup, not empty) and the body vector (§9.2.6).
struct FocusedView {
  const ShadowInput& in;
  glm::dvec3 l;
  std::span<const glm::dvec3> bodyVertices;
  glm::dvec3 bodyVector;
};

// What the methods fitted to the view share (uniform, lispsm, tsm): V ∩ S (∩ receivers), the
// points the map must hold (B's vertices and V ∩ S's, and ShadowInput::alsoCover: B and V ∩ S are clipped with tolerances
// relative to each body's size, and a B 10⁵ times taller than wide can lose 1e-3 of its width to
// them, so the fit takes both), and the light frame L rooted at the eye (§9.2.3; L_r is the
// identity for a directional light: the body vector already points "up" the map).
struct FittedView {
  ConvexBody visible;
  std::pmr::vector<glm::dvec3> fitVertices;
  glm::dmat4 lightFrame{1.0};
  // V ∩ S, or B where V ∩ S came out empty (tolerances).
  const ConvexBody& visibleOr(const ConvexBody& body) const { return visible.empty() ? body : visible; }
};
FittedView fitView(const FocusedView& view);

// A method's matrices (and diagnostics) into `setup`, which holds B; float32 is checked after.
using MethodSetup = void (*)(const FocusedView& view, ShadowSetup& setup);
// What a method carries to the next frame for the same slice (ShadowInput::carried); 0: nothing.
using MethodCarry = double (*)(const ShadowSetup& setup);

struct ShadowMethodUnit {
  ShadowMethod method;
  MethodSetup setup;
  MethodCarry carry;
  std::string_view float32FallbackNote;  // the diagnostics' note when float32 forces the uniform map
  bool compared;                          // in comparisons of methods (comparedShadowMethods)
  bool holdsStillByItself;                // its map does not swim as the camera moves: never kept (kept_slices.hpp)
};
const ShadowMethodUnit& methodUnit(ShadowMethod method);

// The rows' functions, each in its method's file.
void setupUniform(const FocusedView& view, ShadowSetup& setup);        // method_uniform.cpp
void setupUniformStable(const FocusedView& view, ShadowSetup& setup);  // method_uniform_stable.cpp
double carryStableRadius(const ShadowSetup& setup);
void setupLispsm(const FocusedView& view, ShadowSetup& setup);         // method_lispsm.cpp
double carryLispsmN(const ShadowSetup& setup);
void setupTsm(const FocusedView& view, ShadowSetup& setup);            // method_tsm.cpp
void setupTsmIterative(const FocusedView& view, ShadowSetup& setup);
inline double carryNothing(const ShadowSetup&) { return 0.0; }

}  // namespace forest::shadows
