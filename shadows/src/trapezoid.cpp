#include "trapezoid.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "forest/core/polygon2d.hpp"
#include "forest/shadows/shadow_setup.hpp"

namespace forest::shadows {
namespace {

using glm::dvec2;

// Below this share of the footprint's size the centre line has no direction (§6.1's coincident
// near and far centres).
constexpr double kCentreLineShare = 1e-6;
// η is kept within [kMinEtaShare, kMaxEtaShare]·λ: η → 0 collapses the top edge to a point (the
// focus point on the top line), η → ∞ is the limit rectangle (no finite q maps the focus point
// to ξ); both limits are approached continuously.
constexpr double kMinEtaShare = 1e-3;
constexpr double kMaxEtaShare = 1e3;
// The trapezoid is at least this share of λ wide at its base (a footprint that is a segment).
constexpr double kMinWidthShare = 1e-3;
// The iterative variant tries focus lines from the 80% line up to the 20% line, at most this many.
constexpr int kMaxIterations = 128;
constexpr double kLastFocusLine = 0.6;

// The part of a convex polygon where along(p) ≤ limit (Sutherland–Hodgman, one plane).
std::vector<dvec2> clipBelow(const std::vector<dvec2>& polygon, const dvec2& axis, double offset, double limit) {
  std::vector<dvec2> out;
  for (size_t i = 0; i < polygon.size(); ++i) {
    const dvec2& a = polygon[i];
    const dvec2& b = polygon[(i + 1) % polygon.size()];
    const double da = glm::dot(a, axis) - offset - limit, db = glm::dot(b, axis) - offset - limit;
    if (da <= 0.0) out.push_back(a);
    if ((da < 0.0) != (db < 0.0) && da != db) out.push_back(a + (b - a) * (da / (da - db)));
  }
  return out;
}

dvec2 apply(const glm::dmat3& h, const dvec2& p) {
  const glm::dvec3 r = h * glm::dvec3(p, 1.0);
  return dvec2(r) / r.z;
}

}  // namespace

double tsmProjectionDistance(double lambda, double deltaPrime, double xi) {
  const double denominator = lambda - 2.0 * deltaPrime - lambda * xi;
  if (!(denominator > 0.0)) return std::numeric_limits<double>::infinity();
  return lambda * deltaPrime * (1.0 + xi) / denominator;
}

std::optional<Trapezoid> computeTrapezoid(const TrapezoidInput& in, std::string_view& why) {
  const std::vector<dvec2> hull = convexHull(in.footprint);
  double size = 0.0;
  for (const dvec2& p : hull) size = std::max(size, glm::distance(p, hull.front()));
  // §6.4: the centre line runs from the eye through the centre of the visible part.
  const dvec2 line = in.centre - in.eye;
  if (hull.size() < 2 || !(glm::length(line) > kCentreLineShare * size)) {
    why = "no centre line (view along the light): uniform";
    return std::nullopt;
  }
  const dvec2 u = glm::normalize(line), v(-u.y, u.x);
  // §6.1: top line (near the eye) and base line, orthogonal to the centre line, touching the hull.
  double top = std::numeric_limits<double>::max(), base = std::numeric_limits<double>::lowest();
  for (const dvec2& p : hull) {
    top = std::min(top, glm::dot(p - in.eye, u));
    base = std::max(base, glm::dot(p - in.eye, u));
  }
  Trapezoid t;
  t.lambda = base - top;
  if (!(t.lambda > kCentreLineShare * size)) {
    why = "footprint flat along the centre line: uniform";
    return std::nullopt;
  }
  t.focus = std::clamp(glm::dot(in.focusPoint - in.eye, u) - top, 0.0, t.lambda);

  // The trapezoid for one focus line ξ: q at η beyond the top line, side lines through q touching
  // the hull (§6.2), and N_T. Coordinates relative to q: a along u (≥ η inside), b along v.
  auto build = [&](double xi) {
    Trapezoid r = t;
    r.xi = xi;
    r.eta = std::clamp(tsmProjectionDistance(t.lambda, t.focus, xi), kMinEtaShare * t.lambda, kMaxEtaShare * t.lambda);
    const dvec2 q = in.eye + (top - r.eta) * u;
    double low = std::numeric_limits<double>::max(), high = std::numeric_limits<double>::lowest();
    for (const dvec2& p : hull) {
      const double slope = glm::dot(p - q, v) / glm::dot(p - q, u);
      low = std::min(low, slope);
      high = std::max(high, slope);
    }
    const double minSpread = kMinWidthShare * t.lambda / (r.eta + t.lambda);
    if (high - low < minSpread) {
      const double mid = 0.5 * (high + low);
      low = mid - 0.5 * minSpread;
      high = mid + 0.5 * minSpread;
    }
    // Homogeneous coordinates (a, b, 1) → (x_T·w, y_T·w, w): x_T = (2b/a − (high + low)) /
    // (high − low); y_T = −(λ + 2η)/λ + 2(λ + η)η/(λ a) (the §6.2 matrix); w = a.
    const double lambda = t.lambda, eta = r.eta;
    glm::dmat3 fromQ(0.0);  // columns a, b, 1
    fromQ[0] = glm::dvec3(-(high + low) / (high - low), -(lambda + 2.0 * eta) / lambda, 1.0);
    fromQ[1] = glm::dvec3(2.0 / (high - low), 0.0, 0.0);
    fromQ[2] = glm::dvec3(0.0, 2.0 * (lambda + eta) * eta / lambda, 0.0);
    glm::dmat3 toQ(1.0);  // (x, y, 1) → (a, b, 1)
    toQ[0] = glm::dvec3(u.x, v.x, 0.0);
    toQ[1] = glm::dvec3(u.y, v.y, 0.0);
    toQ[2] = glm::dvec3(-glm::dot(q, u), -glm::dot(q, v), 1.0);
    r.toSquare = fromQ * toQ;
    // The focus region (the hull up to δ' below the top line) in the square, out of its area 4.
    const std::vector<dvec2> focusRegion = clipBelow(hull, u, glm::dot(in.eye, u), top + t.focus);
    std::vector<dvec2> mapped;
    for (const dvec2& p : focusRegion) mapped.push_back(apply(r.toSquare, p));
    r.focusArea = polygonArea(mapped) / 4.0;
    return r;
  };

  Trapezoid best = build(kTsmFocusLine);
  if (in.iterative) {
    // §6.2, iterative: move the focus point's line up one texel line at a time and keep the
    // trapezoid whose focus region covers the largest area of the map.
    const double lineHeight = 2.0 / in.mapLines;
    const int lines = static_cast<int>((kLastFocusLine - kTsmFocusLine) / lineHeight);
    const int stride = std::max(1, lines / kMaxIterations);
    for (int k = stride; k <= lines; k += stride) {
      const Trapezoid candidate = build(kTsmFocusLine + k * lineHeight);
      if (candidate.focusArea > best.focusArea) best = candidate;
    }
  }
  return best;
}

}  // namespace forest::shadows
