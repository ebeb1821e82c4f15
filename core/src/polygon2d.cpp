#include "forest/core/polygon2d.hpp"

#include <algorithm>
#include <cmath>

namespace forest {
namespace {

double cross(const glm::dvec2& o, const glm::dvec2& a, const glm::dvec2& b) {
  return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

}  // namespace

size_t convexHullInPlace(std::span<glm::dvec2> points, std::span<glm::dvec2> hull) {
  std::sort(points.begin(), points.end(), [](const glm::dvec2& a, const glm::dvec2& b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
  const size_t n = static_cast<size_t>(std::unique(points.begin(), points.end()) - points.begin());
  if (n < 3) {
    std::copy_n(points.begin(), n, hull.begin());
    return n;
  }
  size_t k = 0;
  for (size_t i = 0; i < n; ++i) {  // lower chain
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], points[i]) <= 0.0) --k;
    hull[k++] = points[i];
  }
  for (size_t i = n - 1, lower = k + 1; i-- > 0;) {  // upper chain
    while (k >= lower && cross(hull[k - 2], hull[k - 1], points[i]) <= 0.0) --k;
    hull[k++] = points[i];
  }
  return k - 1;
}

std::vector<glm::dvec2> convexHull(std::vector<glm::dvec2> points) {
  std::vector<glm::dvec2> hull(2 * points.size());
  hull.resize(convexHullInPlace(points, hull));
  return hull;
}

double polygonArea(const std::vector<glm::dvec2>& polygon) {
  double twice = 0.0;
  for (size_t i = 0; i < polygon.size(); ++i) {
    const glm::dvec2& a = polygon[i];
    const glm::dvec2& b = polygon[(i + 1) % polygon.size()];
    twice += a.x * b.y - a.y * b.x;
  }
  return 0.5 * std::abs(twice);
}

}  // namespace forest
