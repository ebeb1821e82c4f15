#pragma once
// The six planes of a view frustum (Gribb & Hartmann, "Fast extraction of viewing frustum planes
// from the world-view-projection matrix", 2001), for the engine's zero-to-one clip depth, and a
// conservative box test: false only when the box is certainly outside.
#include <glm/glm.hpp>

#include <array>

#include "forest/core/bounds.hpp"
#include "forest/core/camera.hpp"

namespace forest {

class Frustum {
 public:
  explicit Frustum(const Camera& camera);
  // From clip = viewProjection · world, x, y ∈ [−w, w], z ∈ [0, w].
  explicit Frustum(const glm::dmat4& viewProjection);

  // Outward normals: inside is signedDistance ≤ 0 for all six.
  const std::array<Plane, 6>& planes() const { return planes_; }
  // False only when the box is entirely outside one plane.
  bool mayIntersect(const Aabb& box) const;
  // True when the whole box is inside (every corner on the inner side of all six planes).
  bool contains(const Aabb& box) const;

 private:
  std::array<Plane, 6> planes_;
};

}  // namespace forest
