#pragma once
// The terrain (DESIGN §4 terrain/): the heightfield cut into square tiles of kTileQuads quads —
// the objects the culling hierarchy sees — with exact boxes, and the surface the GPU draws.
//
// Mesh: sample (i, j) is vertex (x, h, z); each quad is split along the diagonal from (i, j) to
// (i+1, j+1), counter-clockwise seen from above. Top surface only: no walls, no bottoms, no
// skirts, so the surface bounds a solid and backside shadow rendering works (DESIGN §4).
//
// LOD (CDLOD-style vertex morphing, Strugar 2009, on fixed tiles): a tile is drawn at level L
// (every 2^L-th sample); vertices odd at level L slide toward their lower-index even neighbour by
// a morph factor k from their distance to the camera, so at k = 1 the tile equals level L+1.
// Levels and morphs are a pure function of the camera (TerrainLod), reproduced on the CPU exactly.
#include <glm/glm.hpp>

#include <array>
#include <limits>
#include <span>
#include <utility>
#include <vector>

#include "forest/core/bounds.hpp"
#include "forest/core/camera.hpp"
#include "forest/terrain/block_facing.hpp"
#include "forest/terrain/heightfield.hpp"

namespace forest::terrain {

constexpr int kTileQuads = 64;     // quads per tile side at level 0
constexpr int kLevels = 7;         // levels 0…6: 64, 32, …, 1 quads per tile side

// The LOD state for one camera: distances (metres) where the morph from level L to L+1 starts
// and ends. Chosen so that (1) the projected vertical error of the surface stays below
// `errorPixels`: morphStart[L] ≥ ε(L+1) · K / τ with K = viewport height / (2 tan(fovy/2)), ε the
// largest vertical error of level L+1 against the full heightfield; and (2) neighbouring tiles
// never crack: morphStart[L+1] ≥ morphEnd[L] + tile diagonal, which makes every edge between a
// level-L and a level-(L+1) tile lie where the finer tile is fully morphed and the coarser one is
// not morphing, so both draw the same vertices there.
struct TerrainLod {
  // A morph ramp reaches 0 and 1 this share of its width early (morphFactor; terrain.vert).
  static constexpr double kMorphSlack = 1e-3;

  glm::dvec3 eye{0.0};
  std::array<double, kLevels - 1> morphStart{};
  std::array<double, kLevels - 1> morphEnd{};
  double errorPixels = 1.0;

  // Continuous level λ at a distance: L + ramp inside [morphStart[L], morphEnd[L]].
  double levelAt(double distance) const;
  // Morph factor toward level L+1 for a vertex at `distance`, drawn at level L. Reaches 0 and 1
  // a thousandth of the ramp inside its ends, so float rounding on the GPU cannot leave a
  // fully-morphed edge vertex short of its target (the same formula runs in terrain.vert).
  double morphFactor(int level, double distance) const;
};

// Cells [first, end) of a block, in blockGridIndices' order (row by row, two triangles each);
// an end past cellsPerBlock(level) reaches the block's last cell.
struct CellSpan {
  static constexpr int kToTheLast = std::numeric_limits<int>::max();
  int first = 0, end = kToTheLast;
  bool empty() const { return end <= first; }
};

// Block `block` (row-major, blocksPerTile(level) of them) of a tile drawn at `level`: its cells
// `cells` (all by default).
struct TileBlock {
  int tile = 0, level = 0, block = 0;
  CellSpan cells{};
};

struct TerrainTriangle {
  std::array<glm::dvec3, 3> vertices;  // counter-clockwise seen from above
};

class Terrain {
 public:
  explicit Terrain(const TerrainSettings& settings);

  const Heightfield& heightfield() const { return heightfield_; }
  const TerrainSettings& settings() const { return settings_; }
  int tilesPerSide() const { return tilesPerSide_; }
  int tileCount() const { return tilesPerSide_ * tilesPerSide_; }
  // Tile t covers samples [tx·64, tx·64 + 64] × [tz·64, tz·64 + 64], t = tz · tilesPerSide + tx.
  const Aabb& tileBox(int tile) const { return tileBoxes_[tile]; }
  const std::vector<Aabb>& tileBoxes() const { return tileBoxes_; }
  // Tighter boxes of a tile drawn at `level`, whose union holds everything drawn of it: the boxes
  // of its blocks of B = max(16, 2^(level+1)) quads (16, 4 or 1 of them). A level-L cell and the
  // coarser cell its vertices morph toward (2^(L+1) quads) lie inside one such block, so every
  // drawn vertex over a block is a mix of that block's samples.
  std::span<const Aabb> blockBoxes(int tile, int level) const;
  static constexpr int kMaxBlockBoxes = (kTileQuads / 16) * (kTileQuads / 16);
  // The cells of block `block` of a tile drawn at `level` that may write into a backside shadow
  // map for a sun, in the morph state `lod` gives it (blockMorph), appended to `runs` as runs of
  // consecutive cells. Outside a morph ramp by its slopes' support (BlockFacing): all cells or
  // none. Inside one triangle by triangle at the LOD's morph factors: each run of cells with a
  // triangle that may face away; the other cells write nothing there.
  void cellsThatMayFaceAway(int tile, int level, int block, const TerrainLod& lod, const glm::dvec3& toSun,
                            std::vector<CellSpan>& runs) const;
  // Whether any cell of the block may (cellsThatMayFaceAway).
  bool blockMayFaceAway(int tile, int level, int block, const TerrainLod& lod, const glm::dvec3& toSun) const;
  // Every vertex of the block at k = 0 (its box ends before the level's morph ramp), at k = 1 (it
  // starts past the ramp) or either.
  BlockMorph blockMorph(int tile, int level, int block, const TerrainLod& lod) const;
  Aabb bounds() const { return bounds_; }
  // Largest vertical distance between the level-L mesh and the samples it skips, over all tiles
  // (0 for level 0).
  double levelError(int level) const { return levelError_[level]; }

  // Height and interpolated vertex normal of the full-resolution mesh (level 0) at world (x, z),
  // with the drawn triangle split; (x, z) outside the terrain is clamped to its border.
  double heightAt(double x, double z) const;
  glm::dvec3 normalAt(double x, double z) const;

  // The LOD for a camera drawing an image `viewportHeight` pixels high.
  TerrainLod lodFor(const Camera& camera, int viewportHeight) const;
  // The level a tile is drawn at: floor(λ(distance from the eye to the tile's box)).
  int tileLevel(int tile, const TerrainLod& lod) const;
  // The drawn (morphed) vertex for local sample (i, j) of a tile at `level` — the CPU twin of
  // terrain.vert.
  glm::dvec3 drawnVertex(int tile, int i, int j, int level, const TerrainLod& lod) const;
  // The triangles the GPU draws for a tile (degenerate ones included).
  std::vector<TerrainTriangle> drawnTriangles(int tile, const TerrainLod& lod) const;
  // Height of the drawn surface at world (x, z): the tile's drawn triangle over (x, z).
  double drawnHeightAt(double x, double z, const TerrainLod& lod) const;

  // Bytes the GPU holds for the terrain (height texture + shared grids), and per km².
  size_t gpuBytes() const;
  double gpuBytesPerSquareKilometre() const;

 private:
  int tileOf(double x, double z) const;
  // Local sample (i, j) of a tile at `level` and the sample it slides to (odd at the level: one
  // step lower), world positions: the two ends of its morph (drawnVertex).
  std::pair<glm::dvec3, glm::dvec3> morphEnds(int tile, int i, int j, int level) const;
  // cellsThatMayFaceAway for a block inside a morph ramp (ramp_block_facing.cpp).
  void rampCellsThatMayFaceAway(int tile, int level, int block, const TerrainLod& lod, const glm::dvec3& toSun,
                                std::vector<CellSpan>& runs) const;

  TerrainSettings settings_;
  Heightfield heightfield_;
  int tilesPerSide_ = 0;
  std::vector<Aabb> tileBoxes_;
  std::vector<Aabb> blocks16_, blocks32_;  // per tile: 16 and 4 block boxes, row-major
  BlockFacing blockFacing_;
  Aabb bounds_;
  std::array<double, kLevels> levelError_{};
  double tileDiagonal_ = 0.0;
};

// Index list (triangles) of the level-L grid of one tile over the (kTileQuads + 1)² local
// vertices, row-major in (i, j) with i along x: what the GPU draws for every tile at that level.
std::vector<std::uint32_t> tileGridIndices(int level);
// The same for block 0 of a tile at that level (blockQuads(level) quads per side, same vertex
// numbering): a block elsewhere in the tile is this list with its block's origin added to every
// vertex's (i, j) (terrain.vert).
std::vector<std::uint32_t> blockGridIndices(int level);

}  // namespace forest::terrain
