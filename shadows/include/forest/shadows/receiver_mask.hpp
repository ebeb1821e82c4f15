#pragma once
// A receiver mask in light space (Bittner et al. 2011, "Shadow Caster Culling for Efficient Shadow
// Mapping", §4): the visible receiver points of a frame — one per pixel facing the sun —
// projected into one shadow map; each cell of a coarse grid over the map keeps the largest map
// depth of its points (the one farthest from the light). A caster can darken one of them only if
// its box, projected into the map and grown by what the filter reads, covers a cell whose farthest
// receiver lies beyond the box's nearest point. Box casters, pixel receivers: exact, and much
// tighter than receiver boxes where a receiver box spans a tree or a terrain tile.
// Tighter than the paper's rectangle of cells, at no cost in depth storage: each cell also keeps
// which of its 4 × 4 sub-cells hold a receiver (a bit each), and a cell counts for a box only when
// one of those sub-cells, grown by the reach, meets the box's outline in the map (the convex hull
// of its projected corners, not their bounding rectangle). A finer grid of depths would cut about
// as much and cost ~3 ms a frame at 800 × 600 (DESIGN §4).
#include <glm/glm.hpp>

#include <cstdint>
#include <span>
#include <vector>

#include "forest/core/bounds.hpp"
#include "forest/shadows/shadow_setup.hpp"

namespace forest::shadows {

// The eye's position and orthonormal basis.
struct EyeRays {
  glm::dvec3 eye, forward, right, up;
};

class ReceiverMask {
 public:
  // Empties the mask for one map (its setup, texels per side) with `cells` × `cells` cells. Keeps
  // its storage (no allocation once it has held that many cells).
  void reset(const ShadowSetup& setup, int mapSize, int cells);
  // A receiver point (world). Points outside the map read its border texels (clamped) and count
  // there.
  void add(const glm::dvec3& world);
  // One row of an image seen from the eye (a frame hands over every row): pixel i's receiver is
  // eye + depths[i] · (forward + columns[i] · right + row · up), as add() would take it, when
  // zMin ≤ depths[i] ≤ zMax (0: no receiver at that pixel). The map's transform is applied to the
  // row's rays once, so each pixel costs a few multiply-adds and one division. Floats, as the GPU
  // places the pixel (its eye depth is a float in the G-buffer).
  void addEyeRow(const EyeRays& rays, float row, std::span<const float> columns, std::span<const float> depths, double zMin,
                 double zMax);
  // Takes the points of `other`, a mask reset for the same map and cells (filled from another part
  // of the points, e.g. on another thread): per cell the farther depth, the receivers of both.
  // In parts (threads): part p of `parts` merges that share of the cells, part 0 the counts.
  void merge(const ReceiverMask& other, int part = 0, int parts = 1);
  // False only when no receiver the filter can reach from the caster's texels lies farther from
  // the light than the box: `reachTexels` is how far (in texels, per axis) a lookup reads from its
  // point. True when the box reaches behind the light's projection (w ≤ 0 at a corner).
  bool mayShadow(const Aabb& caster, double reachTexels) const;
  int receivers() const { return receivers_; }

 private:
  static constexpr int kSubCells = 4;  // sub-cells per cell and axis (a cell's bits fit 16)
  int subCellOf(double ndc) const;      // [−1, 1] → [0, cells · kSubCells), clamped
  struct Writer;  // places receiver points (receiver_mask.cpp)
  // The map depth of a world point (clip z / w, or tsm's linear light depth), given its clip h.
  double depthOf(const glm::dvec3& world, const glm::dvec4& clip) const;

  // What the mask needs of the map's setup (ShadowSetup: the matrices, not the focus body).
  glm::dmat4 worldToShadowClip_{1.0};
  bool linearDepth_ = false;
  glm::dvec4 worldToLightDepth_{0.0};
  int mapSize_ = 1, side_ = 0, receivers_ = 0;  // side_: cells per side
  bool everywhere_ = false;  // a receiver with w ≤ 0 was added
  struct Cell {
    std::uint16_t farthest;  // the largest receiver depth, coded (receiver_mask.cpp); 0 when none
    std::uint16_t occupied;  // bit kSubCells · j + i: sub-cell (i, j) holds a receiver (none: 0)
  };
  std::vector<Cell> cells_;  // row by row: 4 bytes a cell, as the paper's float depth alone
};

}  // namespace forest::shadows
