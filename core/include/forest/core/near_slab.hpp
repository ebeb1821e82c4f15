#pragma once
// Where an occlusion query of a box can be trusted. A query rasterises the box's front faces, and
// the near plane clips those closer than z_n. A point P inside the box that the eye sees is still
// found when the ray from the eye to P enters the box at depth ≥ z_n: the entry face is drawn
// there, in front of P. Were the entry closer, the ray — which lies in the view frustum — would
// cross the near plane inside the box, so a box that misses the near rectangle (the frustum's face
// at z_n) is queried safely, and one that meets it must count as visible (CHC++ §3.6 asks this only
// of boxes that hold the eye; a box beside the eye that reaches behind the near plane outside the
// view is safe to query). The test uses the frustum's slab from z_n to (1 + kDepth) z_n and grows
// the box by kDepth z_n, so that entries within that margin of the clip, and rounding in the box's
// faces, count as clipped.
#include <array>

#include "forest/core/bounds.hpp"
#include "forest/core/camera.hpp"

namespace forest {

class NearSlab {
 public:
  static constexpr double kDepth = 1e-3;  // of z_n: 0.1 mm at z_n = 0.1 m, far above float rounding of clip depth

  explicit NearSlab(const Camera& camera);
  // True when the box, grown by kDepth · z_n, meets the slab: a query of it could miss what it holds.
  // Exact for the two convex bodies (separating axes: the box's 3 face normals, the slab's 5, and
  // the 18 cross products of their edge directions); allocates nothing.
  bool meets(const Aabb& box) const;

 private:
  static constexpr int kAxes = 3 + 5 + 3 * 6;
  glm::dvec3 eye_;
  double margin_;
  std::array<glm::dvec3, kAxes> axes_;
  std::array<double, kAxes> slabMin_, slabMax_;  // the slab's extent along each axis, eye-relative
};

}  // namespace forest
