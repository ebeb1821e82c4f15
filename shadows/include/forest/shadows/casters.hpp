#pragma once
// Shadow caster selection in light space (DESIGN §4, after Bittner et al., "Shadow Caster
// Culling for Efficient Shadow Mapping", I3D 2011): an object must be drawn into the shadow map
// iff its box, swept along the light direction, meets the box of a visible receiver. Never
// chosen by eye visibility: a tree hidden behind a hill still shadows the visible valley.
#include <glm/glm.hpp>

#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "forest/core/bounds.hpp"
#include "forest/core/convex_body.hpp"

namespace forest::shadows {

// Unit axes across the light direction l (unit): u ⟂ v ⟂ l with u × v = l.
std::pair<glm::dvec3, glm::dvec3> axesAcrossLight(const glm::dvec3& l);

// Exact for boxes: C swept along l meets R iff some t ≥ 0 has t·l in the Minkowski difference
// R ⊖ C = [R.min − C.max, R.max − C.min], a ray-box test.
bool sweptBoxMeetsBox(const Aabb& caster, const glm::dvec3& lightDirection, const Aabb& receiver);

// The receivers' footprints on a 2D grid in the plane across the light, so a caster is tested
// only against receivers whose footprint overlaps its own.
class CasterSelector {
 public:
  // `lightDirection`: the way light travels (need not be unit). Receivers are copied.
  CasterSelector(const glm::dvec3& lightDirection, std::span<const Aabb> receivers);

  // True iff the caster's box swept along the light meets some receiver's box.
  bool needed(const Aabb& caster) const;
  // Indices of the casters that are needed, in increasing order.
  std::vector<std::uint32_t> select(std::span<const Aabb> casters) const;

  std::size_t receiverCount() const { return receivers_.size(); }

 private:
  struct Footprint {
    glm::dvec2 min, max;
  };
  Footprint footprint(const Aabb& box) const;
  glm::ivec2 cellOf(const glm::dvec2& p) const;

  glm::dvec3 light_;
  glm::dvec3 across_[2];  // unit axes of the plane across the light
  std::vector<Aabb> receivers_;
  glm::dvec2 gridMin_{0.0}, cellSize_{1.0};
  glm::ivec2 gridCells_{0};
  std::vector<std::vector<std::uint32_t>> cells_;  // receiver indices per cell, row-major
};

// Conservative overlap of a convex body and a box (separating planes: B's faces and the box's
// faces): false only when they are certainly apart. Used to count the casters a frustum-based B
// would select.
bool mayIntersect(const ConvexBody& body, const Aabb& box);

}  // namespace forest::shadows
