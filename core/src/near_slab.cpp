#include "forest/core/near_slab.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace forest {

NearSlab::NearSlab(const Camera& camera) : eye_(camera.position), margin_(kDepth * camera.near) {
  // The slab's 8 corners, eye-relative: the frustum's cross-sections at z_n and (1 + kDepth) z_n.
  const glm::dvec3 f = camera.forward(), r = camera.right(), u = camera.up();
  const double tanHalf = std::tan(0.5 * camera.fovy);
  std::array<glm::dvec3, 8> corners;
  std::array<glm::dvec3, 4> lateral;  // the directions of the 4 edges from the near to the far face
  for (int c = 0; c < 4; ++c) {
    const double sx = c & 1 ? 1.0 : -1.0, sy = c & 2 ? 1.0 : -1.0;
    lateral[c] = f + sx * tanHalf * camera.aspect * r + sy * tanHalf * u;
    corners[c] = camera.near * lateral[c];
    corners[c + 4] = camera.near * (1.0 + kDepth) * lateral[c];
  }
  int n = 0;
  axes_[n++] = f;  // near and far faces: first, as they part the slab from most boxes
  for (int k = 0; k < 3; ++k) axes_[n++] = glm::dvec3(k == 0, k == 1, k == 2);  // the box's faces
  // The 4 side faces: each holds the eye and two neighbouring lateral edges.
  const int ring[4] = {0, 1, 3, 2};
  for (int k = 0; k < 4; ++k) axes_[n++] = glm::cross(lateral[ring[k]], lateral[ring[(k + 1) % 4]]);
  const std::array<glm::dvec3, 6> slabEdges = {r, u, lateral[0], lateral[1], lateral[2], lateral[3]};
  for (int k = 0; k < 3; ++k)
    for (const glm::dvec3& e : slabEdges) axes_[n++] = glm::cross(glm::dvec3(k == 0, k == 1, k == 2), e);
  for (int a = 0; a < kAxes; ++a) {
    slabMin_[a] = std::numeric_limits<double>::infinity();
    slabMax_[a] = -slabMin_[a];
    for (const glm::dvec3& p : corners) {
      const double d = glm::dot(axes_[a], p);
      slabMin_[a] = std::min(slabMin_[a], d);
      slabMax_[a] = std::max(slabMax_[a], d);
    }
  }
}

bool NearSlab::meets(const Aabb& box) const {
  if (!box.valid()) return false;  // an empty box holds nothing to lose
  const glm::dvec3 centre = box.centre() - eye_, half = 0.5 * box.extent() + glm::dvec3(margin_);
  for (int a = 0; a < kAxes; ++a) {
    // An edge parallel to a box axis gives a zero cross product: no axis (the faces cover it).
    const glm::dvec3& axis = axes_[a];
    const double c = glm::dot(axis, centre), radius = glm::dot(glm::abs(axis), half);
    if (c + radius < slabMin_[a] || c - radius > slabMax_[a]) return false;  // a separating axis
  }
  return true;
}

}  // namespace forest
