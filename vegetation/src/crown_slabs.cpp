#include "forest/vegetation/crown_slabs.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "forest/core/error.hpp"

namespace forest::vegetation {

using glm::dvec2;
using glm::dvec3;

double CrownSlab::radiusAt(double y) const {
  if (!(top > bottom)) return std::max(radiusBottom, radiusTop);
  const double s = std::clamp((y - bottom) / (top - bottom), 0.0, 1.0);
  return radiusBottom + (radiusTop - radiusBottom) * s;
}

std::array<dvec3, 16> PlacedCrownSlab::corners() const {
  // An octagon of apothem ρ has its corners at ρ / cos(π/8), at π/8 + k·π/4.
  // (cos, sin) of π/8 + k·π/4 over cos(π/8): the corners' directions at unit apothem, computed
  // once (the hidden-caster test takes a million trees' corners a frame).
  static const std::array<glm::dvec2, 8> kCorners = [] {
    std::array<glm::dvec2, 8> d;
    for (int k = 0; k < 8; ++k) {
      const double angle = std::numbers::pi / 8.0 + k * std::numbers::pi / 4.0;
      d[static_cast<size_t>(k)] = glm::dvec2(std::cos(angle), std::sin(angle)) / std::cos(std::numbers::pi / 8.0);
    }
    return d;
  }();
  std::array<dvec3, 16> c;
  for (int end = 0; end < 2; ++end) {
    const double y = end == 0 ? bottom : top, r = end == 0 ? radiusBottom : radiusTop;
    for (int k = 0; k < 8; ++k) {
      const glm::dvec2 d = r * kCorners[static_cast<size_t>(k)];
      c[static_cast<size_t>(8 * end + k)] = base + dvec3(d.x, y - base.y, d.y);
    }
  }
  return c;
}

std::optional<dvec2> PlacedCrownSlab::lineSpan(const dvec3& a, const dvec3& d, double grow) const {
  const dvec3 p = a - base;  // relative to the axis's foot
  const double yBottom = bottom - base.y, yTop = top - base.y;
  const double slope = yTop > yBottom ? (radiusTop - radiusBottom) / (yTop - yBottom) : 0.0;
  double sNear = -std::numeric_limits<double>::infinity(), sFar = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 10; ++i) {
    // Face i as n·q ≤ k: the floor, the roof, then the eight sides n·(x, z) ≤ ρ(y) = radiusBottom +
    // slope (y − bottom), moved out by grow · |n| (|n| ≤ 1 + |slope|).
    dvec3 n;
    double k;
    if (i == 0) {
      n = dvec3(0.0, -1.0, 0.0);
      k = -(yBottom - grow);
    } else if (i == 1) {
      n = dvec3(0.0, 1.0, 0.0);
      k = yTop + grow;
    } else {
      const double angle = (i - 2) * std::numbers::pi / 4.0;
      n = dvec3(std::cos(angle), -slope, std::sin(angle));
      k = radiusBottom - slope * yBottom + grow * (1.0 + std::abs(slope));
    }
    const double along = glm::dot(n, d), room = k - glm::dot(n, p);  // inside: room − s·along ≥ 0
    if (along == 0.0) {
      if (room < 0.0) return std::nullopt;
      continue;
    }
    const double s = room / along;
    if (along > 0.0) sFar = std::min(sFar, s);
    else sNear = std::max(sNear, s);
  }
  if (!(sNear <= sFar)) return std::nullopt;
  return dvec2(sNear, sFar);
}

Aabb PlacedCrownSlab::grownBounds(double grow) const {
  // lineSpan's body at height y has the apothem ρ(y) + grow (1 + |slope|), ρ extrapolated over
  // [bottom − grow, top + grow]: at most max(radii) + grow |slope| + grow (1 + |slope|); an
  // octagon's x and z extents are its apothem.
  const double height = top - bottom;
  const double slope = height > 0.0 ? std::abs(radiusTop - radiusBottom) / height : 0.0;
  const double r = std::max(radiusBottom, radiusTop) + grow * (1.0 + 2.0 * slope);
  return Aabb{dvec3(base.x - r, bottom - grow, base.z - r), dvec3(base.x + r, top + grow, base.z + r)};
}

namespace {

// The corners of triangle abc's part with height in [low, high] (Sutherland–Hodgman against the two
// planes), appended as (height, distance from the y axis).
void appendClippedCorners(const dvec3& a, const dvec3& b, const dvec3& c, double low, double high, std::vector<dvec2>& out) {
  std::vector<dvec3> polygon{a, b, c}, next;
  for (int side = 0; side < 2; ++side) {
    // Inside: y ≥ low (side 0) or y ≤ high (side 1), as a signed distance ≥ 0.
    auto inside = [&](const dvec3& p) { return side == 0 ? p.y - low : high - p.y; };
    next.clear();
    for (size_t i = 0; i < polygon.size(); ++i) {
      const dvec3& p = polygon[i];
      const dvec3& q = polygon[(i + 1) % polygon.size()];
      const double dp = inside(p), dq = inside(q);
      if (dp >= 0.0) next.push_back(p);
      if ((dp >= 0.0) != (dq >= 0.0)) {
        dvec3 cut = p + (q - p) * (dp / (dp - dq));
        cut.y = side == 0 ? low : high;  // exactly on the plane
        next.push_back(cut);
      }
    }
    polygon.swap(next);
    if (polygon.empty()) return;
  }
  for (const dvec3& p : polygon) out.emplace_back(p.y, std::hypot(p.x, p.z));
}

// The upper convex hull of points (height, radius), by increasing height: the only points an affine
// bound from above can touch.
std::vector<dvec2> upperHull(std::vector<dvec2> points) {
  std::sort(points.begin(), points.end(), [](const dvec2& p, const dvec2& q) { return p.x < q.x || (p.x == q.x && p.y > q.y); });
  std::vector<dvec2> hull;
  for (const dvec2& p : points) {
    if (!hull.empty() && hull.back().x == p.x) continue;  // the same height, no larger radius
    while (hull.size() >= 2) {
      const dvec2 a = hull[hull.size() - 2], b = hull.back();
      // b lies on or below the line from a to p: not on the upper hull.
      if ((b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x) >= 0.0) hull.pop_back();
      else break;
    }
    hull.push_back(p);
  }
  return hull;
}

// The slab of these points: their height range and widest point, and the least-mean-radius affine
// bound r(y) ≥ every point's over the range that stays within the cylinder — among the lines
// through edges of the upper hull (each holds every point) and the cylinder itself, the least at the
// middle height.
CrownSlab fitSlab(const std::vector<dvec2>& points) {
  CrownSlab slab;
  if (points.empty()) return slab;
  slab.bottom = std::numeric_limits<double>::infinity();
  slab.top = -slab.bottom;
  for (const dvec2& p : points) {
    slab.bottom = std::min(slab.bottom, p.x);
    slab.top = std::max(slab.top, p.x);
    slab.radius = std::max(slab.radius, p.y);
  }
  const double span = slab.top - slab.bottom, margin = 1e-9 * std::max(1.0, slab.radius);
  const double cylinder = slab.radius + 2.0 * margin;  // the widest point, lifted as the lines are
  slab.radiusBottom = slab.radiusTop = cylinder;
  const std::vector<dvec2> hull = upperHull(points);
  for (size_t e = 0; span > 0.0 && e + 1 < hull.size(); ++e) {
    const dvec2 a = hull[e], b = hull[e + 1];
    const double slope = (b.y - a.y) / (b.x - a.x);
    double r0 = a.y + slope * (slab.bottom - a.x), r1 = a.y + slope * (slab.top - a.x);
    // Rounding: lift the line until it holds every hull point as computed (the rest lie below them).
    double lift = 0.0;
    for (const dvec2& p : hull) lift = std::max(lift, p.y - (r0 + (r1 - r0) * ((p.x - slab.bottom) / span)));
    r0 = std::max(0.0, r0 + lift + margin);
    r1 = std::max(0.0, r1 + lift + margin);
    if (r0 <= cylinder && r1 <= cylinder && r0 + r1 < slab.radiusBottom + slab.radiusTop) {
      slab.radiusBottom = r0;
      slab.radiusTop = r1;
    }
  }
  slab.radius = std::max(slab.radiusBottom, slab.radiusTop);  // the widest point, lifted by at most 2 · margin
  return slab;
}

// The species' triangle parts in `cells` equal height cells of `bounds`: per cell the upper hull of
// its parts' corners (height, distance from the axis).
std::vector<std::vector<dvec2>> cellHulls(const SpeciesModel& model, const Aabb& bounds, int cells) {
  std::vector<std::vector<dvec2>> corners(static_cast<size_t>(cells));
  const double bottom = bounds.min.y, height = bounds.max.y - bounds.min.y;
  const auto cellOf = [&](double y) {
    if (!(height > 0.0)) return 0;
    return std::clamp(static_cast<int>(std::floor((y - bottom) / height * cells)), 0, cells - 1);
  };
  for (const TreeMesh& mesh : model.lods)
    for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
      const dvec3 a(mesh.positions[mesh.indices[t]]), b(mesh.positions[mesh.indices[t + 1]]), c(mesh.positions[mesh.indices[t + 2]]);
      for (int k = cellOf(std::min({a.y, b.y, c.y})); k <= cellOf(std::max({a.y, b.y, c.y})); ++k) {
        const double low = bottom + height * k / cells, high = k == cells - 1 ? bounds.max.y : bottom + height * (k + 1) / cells;
        appendClippedCorners(a, b, c, low, high, corners[static_cast<size_t>(k)]);
      }
    }
  for (std::vector<dvec2>& cell : corners) cell = upperHull(std::move(cell));
  return corners;
}

// The points of cells [first, end).
std::vector<dvec2> pointsOf(const std::vector<std::vector<dvec2>>& cells, int first, int end) {
  std::vector<dvec2> points;
  for (int k = first; k < end; ++k) points.insert(points.end(), cells[static_cast<size_t>(k)].begin(), cells[static_cast<size_t>(k)].end());
  return points;
}

// What a slab costs: the area of its frustum's outline seen from the side, ∫ 2 r(y) dy.
double outlineArea(const CrownSlab& s) { return s.empty() ? 0.0 : (s.radiusBottom + s.radiusTop) * (s.top - s.bottom); }

}  // namespace

std::vector<CrownSlab> crownSlabs(const SpeciesModel& model, const Aabb& bounds, int count) {
  if (count < 1) throw Error("crownSlabs: expected at least one slab");
  const std::vector<std::vector<dvec2>> cells = cellHulls(model, bounds, count);
  std::vector<CrownSlab> slabs;
  for (int k = 0; k < count; ++k) slabs.push_back(fitSlab(cells[static_cast<size_t>(k)]));
  return slabs;
}

std::vector<CrownSlab> fittedCrownSlabs(const SpeciesModel& model, const Aabb& bounds, int count, int cells) {
  if (count < 1 || cells < count) throw Error("fittedCrownSlabs: expected at least one slab and as many cells");
  const std::vector<std::vector<dvec2>> hulls = cellHulls(model, bounds, cells);
  // cost[i][j]: the slab of cells [i, j); best[n][j]: the least total of n slabs over cells [0, j).
  const auto index = [&](int i, int j) { return static_cast<size_t>(i) * static_cast<size_t>(cells + 1) + static_cast<size_t>(j); };
  std::vector<double> cost(index(cells + 1, 0), 0.0);
  for (int i = 0; i < cells; ++i)
    for (int j = i + 1; j <= cells; ++j) cost[index(i, j)] = outlineArea(fitSlab(pointsOf(hulls, i, j)));
  const double none = std::numeric_limits<double>::infinity();
  std::vector<double> best(index(count + 1, 0), none);
  std::vector<int> cut(index(count + 1, 0), 0);
  best[index(0, 0)] = 0.0;
  for (int n = 1; n <= count; ++n)
    for (int j = n; j <= cells; ++j)
      for (int i = n - 1; i < j; ++i) {
        const double total = best[index(n - 1, i)] + cost[index(i, j)];
        if (total < best[index(n, j)]) {
          best[index(n, j)] = total;
          cut[index(n, j)] = i;
        }
      }
  std::vector<CrownSlab> slabs(static_cast<size_t>(count));
  for (int n = count, j = cells; n >= 1; --n) {
    const int i = cut[index(n, j)];
    slabs[static_cast<size_t>(n - 1)] = fitSlab(pointsOf(hulls, i, j));
    j = i;
  }
  return slabs;
}

}  // namespace forest::vegetation
