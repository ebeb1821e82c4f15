#pragma once
// Axis-aligned boxes and planes, in double precision.
#include <glm/glm.hpp>

#include <array>
#include <limits>

namespace forest {

struct Aabb {
  glm::dvec3 min{std::numeric_limits<double>::infinity()};
  glm::dvec3 max{-std::numeric_limits<double>::infinity()};

  // True once it holds at least one point (a single point is a valid, flat box).
  bool valid() const { return min.x <= max.x && min.y <= max.y && min.z <= max.z; }
  void extend(const glm::dvec3& p) {
    min = glm::min(min, p);
    max = glm::max(max, p);
  }
  void extend(const Aabb& b) {
    min = glm::min(min, b.min);
    max = glm::max(max, b.max);
  }
  glm::dvec3 centre() const { return 0.5 * (min + max); }
  glm::dvec3 extent() const { return max - min; }
  double diagonal() const { return glm::length(max - min); }
  // Distance from p to the nearest point of the box (0 inside).
  double distanceTo(const glm::dvec3& p) const { return glm::length(glm::max(glm::max(min - p, p - max), glm::dvec3(0.0))); }
  bool contains(const glm::dvec3& p, double tolerance = 0.0) const {
    return glm::all(glm::greaterThanEqual(p, min - tolerance)) && glm::all(glm::lessThanEqual(p, max + tolerance));
  }
  // Corner i has x from bit 0, y from bit 1, z from bit 2 (0 = min, 1 = max).
  glm::dvec3 corner(int i) const { return {i & 1 ? max.x : min.x, i & 2 ? max.y : min.y, i & 4 ? max.z : min.z}; }
};

// The plane dot(normal, p) + offset = 0. For a body's face the normal points outward; "inside"
// is signedDistance ≤ 0.
struct Plane {
  glm::dvec3 normal{0.0, 1.0, 0.0};
  double offset = 0.0;

  static Plane through(const glm::dvec3& point, const glm::dvec3& normal) {
    return {normal, -glm::dot(normal, point)};
  }
  double signedDistance(const glm::dvec3& p) const { return glm::dot(normal, p) + offset; }
};

}  // namespace forest
