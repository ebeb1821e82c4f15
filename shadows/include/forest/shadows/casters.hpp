#pragma once
// Shadow caster selection in light space (DESIGN §4, after Bittner et al., "Shadow Caster
// Culling for Efficient Shadow Mapping", I3D 2011): an object must be drawn into the shadow map
// iff its box, swept along the light direction, meets the box of a visible receiver. Never
// chosen by eye visibility: a tree hidden behind a hill still shadows the visible valley.
#include <glm/glm.hpp>

#include <cstdint>
#include <array>
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

// The receivers' footprints on a hierarchical 2D grid in the plane across the light, so a caster is
// tested only against receivers whose footprint may overlap its own: each receiver is filed at the
// finest level where its footprint spans at most kLargeFootprintCells cells an axis, in every cell
// of it that it overlaps, and a caster searches the cells its own footprint overlaps at every level.
// Storage grows with the receivers and is kept from frame to frame (no allocation once it holds a
// frame's). Each cell's
// receivers are ordered by how far along the light they reach, deepest first: the sweep of a caster
// holds only points at least as deep as the caster's nearest, so a cell's scan stops at the first
// receiver that ends before it.
class CasterSelector {
 public:
  // `lightDirection`: the way light travels (need not be unit). Receivers are copied.
  CasterSelector(const glm::dvec3& lightDirection, std::span<const Aabb> receivers);
  CasterSelector() = default;  // no receivers: nothing is needed
  // The same as constructing anew, reusing this selector's storage (a frame builds one per frame).
  void rebuild(const glm::dvec3& lightDirection, std::span<const Aabb> receivers);
  // Room for up to `receivers` receivers: rebuilding with no more than that never allocates.
  void reserve(std::size_t receivers);

  // True iff the caster's box swept along the light meets some receiver's box.
  bool needed(const Aabb& caster) const;
  // Indices of the casters that are needed, in increasing order.
  std::vector<std::uint32_t> select(std::span<const Aabb> casters) const;
  // The same into `selected` (cleared first; its storage reused).
  void select(std::span<const Aabb> casters, std::vector<std::uint32_t>& selected) const;

  std::size_t receiverCount() const { return receivers_.size(); }

 private:
  struct Footprint {
    glm::dvec2 min, max;
  };
  Footprint footprint(const Aabb& box) const;
  // One level of the grid: cells of cellSize from the grid's origin, and its receivers' indices per
  // cell, row-major, in one list: cell c holds items[start[c], start[c + 1]).
  struct Level {
    glm::dvec2 cellSize{1.0};
    glm::ivec2 cells{0};  // 0: an unused level
    std::vector<std::uint32_t> start, items;
  };
  static constexpr double kLargeFootprintCells = 4.0;
  static constexpr int kLevels = 6, kLevelRatio = 4;
  glm::ivec2 cellOf(const Level& level, const glm::dvec2& p) const;
  void fileLevel(Level& level, std::uint8_t k);

  glm::dvec3 light_{0.0, -1.0, 0.0};
  glm::dvec3 across_[2]{};  // unit axes of the plane across the light
  std::vector<Aabb> receivers_;
  std::vector<Footprint> footprints_;
  std::vector<double> deepest_;  // per receiver: the largest depth along the light of a point of it
  std::vector<std::uint8_t> level_;  // per receiver: the level it is filed at
  glm::dvec2 gridMin_{0.0}, cellSize_{1.0};  // level 0's
  glm::ivec2 gridCells_{0};
  std::array<Level, kLevels> levels_;
};

// Conservative overlap of a convex body and a box (separating planes: B's faces and the box's
// faces): false only when they are certainly apart. Used to count the casters a frustum-based B
// would select.
bool mayIntersect(const ConvexBody& body, const Aabb& box);

}  // namespace forest::shadows
