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

#include <cmath>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "forest/core/bounds.hpp"
#include "forest/shadows/shadow_setup.hpp"

namespace forest::shadows {

// The eye's position and orthonormal basis.
struct EyeRays {
  glm::dvec3 eye, forward, right, up;
};

// A rectangle of map texels: columns [x0, x1), rows [y0, y1) (row 0 at v = 0, as glScissor counts).
struct TexelRect {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  bool empty() const { return x1 <= x0 || y1 <= y0; }
  long long texels() const { return empty() ? 0 : static_cast<long long>(x1 - x0) * (y1 - y0); }
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
  // The same for a convex body given by its corners (at most kMaxCorners; a box: its 8).
  static constexpr size_t kMaxCorners = 16;
  bool mayShadow(std::span<const glm::dvec3> caster, double reachTexels) const;
  int receivers() const { return receivers_; }
  // The farthest receiver (map depth as the mask keeps it, at or beyond the true one) among those
  // whose lookups may read texel (x, y) — whose sub-cells lie within `reachTexels` of its centre —
  // or none. Without everywhere().
  std::optional<double> farthestReading(int x, int y, double reachTexels) const;
  // Calls visit(x, y) for each texel a receiver's lookup may read (a texel once per receiver
  // sub-cell that reaches it).
  template <class Visit>
  void forEachTexelRead(double reachTexels, Visit visit) const;
  bool everywhere() const { return everywhere_; }
  // Every texel a lookup at one of the receivers can read, reaching `reachTexels` from its point
  // along each map axis: the rectangle of the occupied sub-cells grown by the reach and clamped to
  // the map. The whole map once a receiver could not be placed; empty without receivers. A shadow
  // pass need not clear or draw texels outside it (most of a LiSPSM map along the thesis walk: the
  // map spans the receivers' boxes, their visible pixels cover less).
  TexelRect texelsRead(double reachTexels) const;

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
  std::vector<std::uint32_t> rowPlaced_;  // addEyeRow's: where a row's pixels go (placeRow)
  std::vector<std::uint16_t> rowCodes_;   // and their depth codes
  struct Cell {
    std::uint16_t farthest;  // the largest receiver depth, coded (receiver_mask.cpp); 0 when none
    std::uint16_t occupied;  // bit kSubCells · j + i: sub-cell (i, j) holds a receiver (none: 0)
  };
  std::vector<Cell> cells_;  // row by row: 4 bytes a cell, as the paper's float depth alone
};

template <class Visit>
void ReceiverMask::forEachTexelRead(double reachTexels, Visit visit) const {
  // Sub-cell s spans texels [s, s + 1) · perSubCell; a lookup in it reads up to the reach beyond:
  // the texels whose centres lie in that range grown by the reach.
  const double perSubCell = static_cast<double>(mapSize_) / (side_ * kSubCells);
  for (int cy = 0; cy < side_; ++cy)
    for (int cx = 0; cx < side_; ++cx) {
      const unsigned bits = cells_[static_cast<size_t>(cy) * side_ + cx].occupied;
      for (int j = 0; bits != 0 && j < kSubCells; ++j)
        for (int i = 0; i < kSubCells; ++i) {
          if ((bits >> (kSubCells * j + i) & 1u) == 0) continue;
          const int sx = cx * kSubCells + i, sy = cy * kSubCells + j;
          const int x0 = std::max(0, static_cast<int>(std::ceil(sx * perSubCell - reachTexels - 0.5)));
          const int x1 = std::min(mapSize_ - 1, static_cast<int>(std::floor((sx + 1) * perSubCell + reachTexels - 0.5)));
          const int y0 = std::max(0, static_cast<int>(std::ceil(sy * perSubCell - reachTexels - 0.5)));
          const int y1 = std::min(mapSize_ - 1, static_cast<int>(std::floor((sy + 1) * perSubCell + reachTexels - 0.5)));
          for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x) visit(x, y);
        }
    }
}

}  // namespace forest::shadows
