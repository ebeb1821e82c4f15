#include "forest/raytrace/clearance.hpp"

#include <algorithm>
#include <array>
#include <vector>

namespace forest::raytrace {
namespace {

// A hit on the segment from a to b (exclusive of its ends' own surfaces), or none.
RayHit segmentHit(const RayScene& scene, const glm::dvec3& a, const glm::dvec3& b) {
  const glm::dvec3 d = b - a;
  const double length = glm::length(d);
  if (!(length > 0.0)) return {};
  return scene.intersect(a, d / length, 0.0, length);
}

}  // namespace

Clearance cameraClearance(const RayScene& scene, const Camera& camera) {
  Clearance result;
  const glm::dvec3 eye = camera.position;
  // Inside: the nearest surface faces away from the eye in most of the six axis directions, on one
  // object. (In every direction, for one closed surface; most, since a component of a tree that
  // reaches into another — a branch into the trunk — shows its front face from inside the other,
  // and a ray that grazes a far mesh's edge can slip between two triangles.)
  const std::array<glm::dvec3, 6> axes{glm::dvec3(1, 0, 0), glm::dvec3(-1, 0, 0), glm::dvec3(0, 1, 0),
                                       glm::dvec3(0, -1, 0), glm::dvec3(0, 0, 1), glm::dvec3(0, 0, -1)};
  std::array<std::uint32_t, 6> insideOf{};
  int backFaces = 0;
  for (const glm::dvec3& axis : axes) {
    const RayHit hit = scene.intersect(eye, axis);
    if (hit.hit && glm::dot(hit.normal, axis) > 0.0) insideOf[static_cast<std::size_t>(backFaces++)] = hit.objectId;
  }
  for (int i = 0; i < backFaces; ++i)
    if (std::count(insideOf.begin(), insideOf.begin() + backFaces, insideOf[static_cast<std::size_t>(i)]) >= 4)
      return {false, insideOf[static_cast<std::size_t>(i)], "the eye is inside"};
  // The near rectangle: its corners, edge midpoints and centre.
  const double halfHeight = camera.near * std::tan(0.5 * camera.fovy), halfWidth = halfHeight * camera.aspect;
  const glm::dvec3 centre = eye + camera.near * camera.forward(), right = halfWidth * camera.right(), up = halfHeight * camera.up();
  std::vector<glm::dvec3> points;
  for (int y = -1; y <= 1; ++y)
    for (int x = -1; x <= 1; ++x) points.push_back(centre + double(x) * right + double(y) * up);
  std::vector<std::pair<glm::dvec3, glm::dvec3>> segments;
  for (const glm::dvec3& p : points) segments.emplace_back(eye, p);
  const auto at = [&](int x, int y) { return points[static_cast<std::size_t>((y + 1) * 3 + (x + 1))]; };
  for (int k = -1; k <= 1; ++k) {
    segments.emplace_back(at(-1, k), at(1, k));  // rows: the bottom and top edges and the middle line
    segments.emplace_back(at(k, -1), at(k, 1));  // columns
  }
  segments.emplace_back(at(-1, -1), at(1, 1));
  segments.emplace_back(at(-1, 1), at(1, -1));
  for (const auto& [a, b] : segments) {
    const RayHit hit = segmentHit(scene, a, b);
    if (hit.hit) return {false, hit.objectId, "it cuts the near plane"};
  }
  return result;
}

}  // namespace forest::raytrace
