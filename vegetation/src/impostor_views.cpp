#include "forest/vegetation/impostor_views.hpp"

#include <algorithm>
#include <cmath>

#include "forest/core/error.hpp"

namespace forest::vegetation {

glm::dvec2 hemiOctahedral(const glm::dvec3& direction) {
  glm::dvec3 d(direction.x, std::max(direction.y, 0.0), direction.z);
  const double l1 = std::abs(d.x) + d.y + std::abs(d.z);
  if (!(l1 > 0.0)) return glm::dvec2(0.0);  // no direction: the zenith's cell (the square's centre)
  d /= l1;
  return {d.x + d.z, d.x - d.z};
}

glm::dvec3 fromHemiOctahedral(const glm::dvec2& square) {
  const double x = 0.5 * (square.x + square.y), z = 0.5 * (square.x - square.y);
  const double y = std::max(0.0, 1.0 - std::abs(x) - std::abs(z));
  return glm::normalize(glm::dvec3(x, y, z));
}

ImpostorGrid::ImpostorGrid(int views) : views_(views) {
  if (views < 1) throw Error("ImpostorGrid: " + std::to_string(views) + " views a side; expected at least 1");
}

ImpostorFrame ImpostorGrid::frame(int i, int j) const {
  const glm::dvec2 centre(2.0 * (i + 0.5) / views_ - 1.0, 2.0 * (j + 0.5) / views_ - 1.0);
  ImpostorFrame f;
  f.toViewer = fromHemiOctahedral(centre);
  const glm::dvec3 side = glm::cross(glm::dvec3(0.0, 1.0, 0.0), f.toViewer);
  f.right = glm::length(side) > 1e-9 ? glm::normalize(side) : glm::dvec3(1.0, 0.0, 0.0);
  f.up = glm::cross(f.toViewer, f.right);
  return f;
}

glm::ivec2 ImpostorGrid::cellOf(const glm::dvec3& direction) const {
  const glm::dvec2 square = hemiOctahedral(direction);
  auto cell = [&](double s) { return std::clamp(static_cast<int>(std::floor((s + 1.0) * 0.5 * views_)), 0, views_ - 1); };
  return {cell(square.x), cell(square.y)};
}

double ImpostorGrid::largestAngle() const {
  double largest = 0.0;
  for (int i = 0; i < views_; ++i)
    for (int j = 0; j < views_; ++j)
      for (int c = 0; c < 4; ++c) {
        const glm::dvec2 corner(2.0 * (i + (c & 1)) / views_ - 1.0, 2.0 * (j + (c >> 1)) / views_ - 1.0);
        largest = std::max(largest, std::acos(std::min(1.0, glm::dot(fromHemiOctahedral(corner), frame(i, j).toViewer))));
      }
  return largest;
}

ImpostorSphere impostorSphere(const SpeciesModel& model) {
  Aabb box;
  for (const TreeMesh& lod : model.lods) box.extend(lod.bounds);
  ImpostorSphere sphere;
  if (!box.valid()) return sphere;
  sphere.centre = box.centre();
  for (const TreeMesh& lod : model.lods)
    for (const glm::vec3& p : lod.positions) sphere.radius = std::max(sphere.radius, glm::distance(glm::dvec3(p), sphere.centre));
  return sphere;
}

}  // namespace forest::vegetation
