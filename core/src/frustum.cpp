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

namespace {

// The corner of the box farthest along `direction`.
glm::dvec3 cornerAlong(const Aabb& box, const glm::dvec3& direction) {
  return {direction.x > 0 ? box.max.x : box.min.x, direction.y > 0 ? box.max.y : box.min.y,
          direction.z > 0 ? box.max.z : box.min.z};
}

}  // namespace

bool Frustum::mayIntersect(const Aabb& box) const {
  // The corner farthest inside (along −normal): if even it is outside, the box is.
  for (const Plane& plane : planes_)
    if (plane.signedDistance(cornerAlong(box, -plane.normal)) > 0.0) return false;
  return true;
}

bool Frustum::contains(const Aabb& box) const {
  // The corner farthest outside (along the normal): if it is inside, every corner is.
  for (const Plane& plane : planes_)
    if (plane.signedDistance(cornerAlong(box, plane.normal)) > 0.0) return false;
  return true;
}

}  // namespace forest
