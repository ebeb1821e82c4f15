#pragma once
// The trapezoidal approximation of TSM §6 (Martin & Tan 2004) in the plane of a uniform shadow
// map: base and top lines (§6.1), side lines through q from the 80% rule (§6.2) or its iterative
// variant, and the trapezoid-to-square map N_T. Module-internal.
#include <glm/glm.hpp>

#include <optional>
#include <string_view>
#include <vector>

namespace forest::shadows {

struct TrapezoidInput {
  std::vector<glm::dvec2> footprint;  // points whose convex hull the trapezoid must contain (B)
  glm::dvec2 eye{0.0};                // the eye, projected into the plane
  glm::dvec2 centre{0.0};             // centre of V ∩ S (∩ receivers), projected (§6.4: e)
  glm::dvec2 focusPoint{0.0};         // the point δ beyond the near plane, projected (§6.2: p_L)
  bool iterative = false;             // §6.2's iterative variant
  int mapLines = 2048;                // texel lines of the map, for the iterative variant's steps
};

struct Trapezoid {
  // N_T as a 3×3 homography on (x, y, 1) of the plane: the trapezoid → [−1, 1]², top edge at
  // y = +1. Columns: n[col][row]. Rows are (x_T·w, y_T·w, w).
  glm::dmat3 toSquare{1.0};
  double lambda = 0.0, focus = 0.0, eta = 0.0, xi = 0.0;
  double focusArea = 0.0;  // the focus region's share of the square
};

// nullopt when there is no centre line (eye and centre project to the same point: the light
// looks along the view) or the footprint has no extent along it; the caller falls back to the
// uniform map then (§6.1: "handled separately").
std::optional<Trapezoid> computeTrapezoid(const TrapezoidInput& input, std::string_view& why);

}  // namespace forest::shadows
