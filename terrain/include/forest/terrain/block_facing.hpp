#pragma once
// Which terrain blocks can write into a backside shadow map (DESIGN §4: the shadow pass draws only
// the faces turned away from the sun). A block whose every drawn triangle faces the sun writes
// nothing there, so the shadow pass skips it — an exact cut, not an estimate: it drops only what
// face culling would drop.
//
// A triangle with upward normal n faces the sun l iff its slope g = (−n_x/n_y, −n_z/n_y) has
// g·l_xz < l_y. A block keeps the support of its triangles' slopes in 16 directions across the
// ground, which bounds g·d for any d between two of them (d = αd_k + βd_{k+1}, α, β ≥ 0) — once
// for its level's mesh unmorphed (every k = 0) and once fully morphed (every k = 1, the coarser
// level's mesh). A block inside a morph ramp mixes the two vertex by vertex, and a triangle's
// n·l is quadratic in a common k, so neither end bounds it: such a block is tested triangle by
// triangle at the frame's own morph factors (Terrain::blockMayFaceAway).
#include <glm/glm.hpp>

#include <vector>

#include "forest/terrain/heightfield.hpp"

namespace forest::terrain {

// Quads per side of the blocks a tile drawn at `level` is cut into (Terrain::blockBoxes): a
// level-L cell and the coarser cell it morphs toward lie in one block.
int blockQuads(int level);
// Blocks per tile at `level` (16, 4 or 1), row-major: block b = bz · (64 / blockQuads) + bx.
int blocksPerTile(int level);
// Cells per block at `level` (16², 8², 4² or 2²), each two triangles, row by row in
// blockGridIndices' order.
int cellsPerBlock(int level);

enum class BlockMorph { Unmorphed, Morphed, Morphing };  // every vertex at k = 0, at k = 1, or between

class BlockFacing {
 public:
  BlockFacing() = default;
  // Every block of every tile at every level (several threads).
  BlockFacing(const Heightfield& heightfield, int tilesPerSide);

  // False only when no triangle drawn over the block at `level` in that morph state faces away
  // from the sun: every one has n̂·toSun ≥ kFacingMargin · toSun_y · n̂_y.
  // `toSun`: unit, toward the sun; a sun at or below the horizon, or a morphing block, gets true.
  bool mayFaceAway(int tile, int level, int block, BlockMorph morph, const glm::dvec3& toSun) const;

  static constexpr int kDirections = 16;
  // A face counts as turned toward the sun when n̂·toSun ≥ kFacingMargin · toSun_y · n̂_y: room
  // for the GPU's float32 transform of its vertices.
  static constexpr double kFacingMargin = 1e-3;

 private:
  static int slotOf(int level, int block);

  // Per tile, per (level, block) slot, unmorphed then morphed: the largest g·d_k over its
  // triangles' slopes, rounded up to float; −∞ when every triangle is collapsed (no fragments).
  std::vector<float> support_;
};

}  // namespace forest::terrain
