#pragma once
// The view directions a far tree's impostor is baked from (issue "Far trees as impostors"): a
// hemi-octahedral grid over the upper hemisphere of directions toward the viewer, in the species'
// object space (base at the origin, up +y). The map folds the octahedron's upper half onto a square:
// d = (x, y, z), y ≥ 0, |x| + |y| + |z| = 1 → (u, v) = (x + z, x − z) ∈ [−1, 1]², so equal cells
// of the square are directions of about equal solid angle and the horizon is the square's border.
// shaders/impostor.glsl evaluates the same map on the GPU.
#include <glm/glm.hpp>

#include "forest/core/bounds.hpp"
#include "forest/vegetation/species.hpp"

namespace forest::vegetation {

// A unit direction with y ≥ 0 (one below the horizon is folded up onto it: y → 0) → its point of
// the square [−1, 1]².
glm::dvec2 hemiOctahedral(const glm::dvec3& direction);
// The square's point → its unit direction (y ≥ 0). hemiOctahedral's inverse.
glm::dvec3 fromHemiOctahedral(const glm::dvec2& square);

// One bake view: the orthographic camera looks along −toViewer; the image's x and y axes are right
// and up (a right-handed frame: right × up = toViewer).
struct ImpostorFrame {
  glm::dvec3 toViewer{0.0, 0.0, 1.0}, right{1.0, 0.0, 0.0}, up{0.0, 1.0, 0.0};
};

// A grid of views × views cells over the square; view (i, j) looks from the direction of its cell's
// centre. right is horizontal (world up × toViewer, normalised), or +x where toViewer is vertical.
class ImpostorGrid {
 public:
  explicit ImpostorGrid(int views);  // views ≥ 1
  int views() const { return views_; }
  ImpostorFrame frame(int i, int j) const;
  // The cell whose square holds the direction (clamped to the grid).
  glm::ivec2 cellOf(const glm::dvec3& direction) const;
  // The largest angle (radians) between a direction and its cell's view: over the cells' corners
  // (the map is affine on each octahedron face, and a cone about the view meets a face in a convex
  // set, so within a cell the angle peaks at a corner; the folds run through the corners).
  double largestAngle() const;

 private:
  int views_;
};

// The sphere every bake view frames: the centre of the species' box over all LODs and the largest
// distance of a vertex of any LOD from it (object space, metres).
struct ImpostorSphere {
  glm::dvec3 centre{0.0};
  double radius = 0.0;
};
ImpostorSphere impostorSphere(const SpeciesModel& model);

}  // namespace forest::vegetation
