#pragma once
// Height slabs of a species' meshes over all LODs (object space): what the culler's queries and the
// shadow caster tests use in place of a tree's one box. Per slab a height range, the cylinder about
// the trunk's axis that holds every triangle's part in it, and a tighter cone frustum — the radius
// affine in height — that holds the same parts (a conifer's tiers taper; a box or a cylinder of the
// widest tier wraps the slab's top in air, which a light's line can cross above the crown).
#include <array>
#include <optional>
#include <vector>

#include "forest/core/bounds.hpp"
#include "forest/vegetation/species.hpp"

namespace forest::vegetation {

constexpr int kQuerySlabs = 4;   // equal height slabs of a tree's query boxes (Forest::treeQueryBoxes)
constexpr int kCasterSlabs = 8;  // fitted slabs of a tree's caster tests (Forest::casterSlabs)
constexpr int kCasterSlabCells = 48;  // the height cells their cuts lie on

struct CrownSlab {
  double bottom = 1.0, top = 0.0;  // height range (object space); bottom > top: no triangle reaches the slab
  double radius = 0.0;             // the largest distance from the y axis of a point in the slab
  // The frustum: distance from the y axis at most radiusBottom + (radiusTop − radiusBottom) · s at
  // height bottom + s · (top − bottom), s in [0, 1]. Both ≤ radius, both ≥ 0.
  double radiusBottom = 0.0, radiusTop = 0.0;
  bool empty() const { return !(bottom <= top); }
  // The frustum's radius at height y (clamped to the slab's range).
  double radiusAt(double y) const;
};

// A crown slab in the world: over `base`, heights [bottom, top] (world y), its frustum's radii at
// them — wrapped in the octagonal frustum whose faces touch the frustum's circles (apothem =
// radius), a convex body of 16 corners and 10 faces.
struct PlacedCrownSlab {
  glm::dvec3 base{0.0};
  double bottom = 0.0, top = 0.0, radiusBottom = 0.0, radiusTop = 0.0;
  std::array<glm::dvec3, 16> corners() const;
  // The parameters [s0, s1] of the line a + s·d inside the octagonal frustum grown by `grow` (its
  // faces moved out by at least that), or none where the line misses it (Cyrus–Beck).
  std::optional<glm::dvec2> lineSpan(const glm::dvec3& a, const glm::dvec3& d, double grow) const;
  // The box that holds the body lineSpan tests with `grow` ≥ 0 (the corners' box at 0).
  Aabb grownBounds(double grow) const;
};

// `count` equal slabs of `bounds`' height (the species' box over all LODs), each cut to the triangle
// parts that reach into it. A slab's frustum is the least in mean radius (its radius at the slab's
// middle height) of those that hold every part: the upper convex hull of the parts' corners in
// (height, distance from the axis) gives it — a frustum is convex, so holding a part's corners
// holds the part.
std::vector<CrownSlab> crownSlabs(const SpeciesModel& model, const Aabb& bounds, int count);
// `count` slabs whose floors and roofs lie on `cells` equal height cells, chosen (dynamic
// programming over the cuts) for the least total outline seen from the side, Σ ∫ 2 r(y) dy: on a
// conifer the cuts fall at its tiers' skirts, so each frustum follows one tier's taper.
std::vector<CrownSlab> fittedCrownSlabs(const SpeciesModel& model, const Aabb& bounds, int count, int cells);

}  // namespace forest::vegetation
