#include "forest/core/frustum.hpp"

namespace forest {

Frustum::Frustum(const Camera& camera) : Frustum(camera.projection() * camera.view()) {}

Frustum::Frustum(const glm::dmat4& m) {
  // Row r of the matrix: m[0][r], m[1][r], m[2][r], m[3][r]. Inside: −w ≤ x ≤ w, −w ≤ y ≤ w,
  // 0 ≤ z ≤ w; each inequality row · p ≥ 0 gives the outward plane −row.
  auto row = [&](int r) { return glm::dvec4(m[0][r], m[1][r], m[2][r], m[3][r]); };
  const glm::dvec4 inside[6] = {row(3) + row(0), row(3) - row(0), row(3) + row(1),
                                row(3) - row(1), row(2),          row(3) - row(2)};
  for (int i = 0; i < 6; ++i) {
    const glm::dvec4 p = -inside[i];
    const double length = glm::length(glm::dvec3(p));
    planes_[static_cast<size_t>(i)] = Plane{glm::dvec3(p) / length, p.w / length};
  }
}

bool Frustum::mayIntersect(const Aabb& box) const {
  for (const Plane& plane : planes_) {
    // The corner farthest inside along −normal: if even it is outside, the box is.
    const glm::dvec3 nearest(plane.normal.x > 0 ? box.min.x : box.max.x, plane.normal.y > 0 ? box.min.y : box.max.y,
                             plane.normal.z > 0 ? box.min.z : box.max.z);
    if (plane.signedDistance(nearest) > 0.0) return false;
  }
  return true;
}

bool Frustum::contains(const Aabb& box) const {
  for (const Plane& plane : planes_) {
    // The corner farthest outside along the normal: if it is inside, every corner is.
    const glm::dvec3 farthest(plane.normal.x > 0 ? box.max.x : box.min.x, plane.normal.y > 0 ? box.max.y : box.min.y,
                              plane.normal.z > 0 ? box.max.z : box.min.z);
    if (plane.signedDistance(farthest) > 0.0) return false;
  }
  return true;
}

}  // namespace forest
