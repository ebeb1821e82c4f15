#include "forest/terrain/terrain.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "forest/core/error.hpp"

namespace forest::terrain {
namespace {

using glm::dvec3;

// Height inside the quad with corner heights h00 (u, v = 0, 0), h10, h01, h11, split along the
// diagonal (0, 0)–(1, 1): triangle (00, 01, 11) where v ≥ u, triangle (00, 11, 10) where u ≥ v.
double quadHeight(double h00, double h10, double h01, double h11, double u, double v) {
  return v >= u ? h00 + u * (h11 - h01) + v * (h01 - h00) : h00 + u * (h10 - h00) + v * (h11 - h10);
}

}  // namespace

double TerrainLod::levelAt(double distance) const {
  for (int level = 0; level < kLevels - 1; ++level) {
    if (distance < morphStart[level]) return level;
    if (distance < morphEnd[level]) return level + (distance - morphStart[level]) / (morphEnd[level] - morphStart[level]);
  }
  return kLevels - 1;
}

double TerrainLod::morphFactor(int level, double distance) const {
  if (level >= kLevels - 1) return 0.0;
  const double t = (distance - morphStart[level]) / (morphEnd[level] - morphStart[level]);
  return std::clamp(t * (1.0 + 2.0 * kMorphSlack) - kMorphSlack, 0.0, 1.0);
}

Terrain::Terrain(const TerrainSettings& settings) : settings_(settings), heightfield_(settings) {
  const Heightfield& h = heightfield_;
  tilesPerSide_ = (h.samples() - 1) / kTileQuads;
  tileBoxes_.resize(static_cast<size_t>(tileCount()));
  for (int tz = 0; tz < tilesPerSide_; ++tz) {
    for (int tx = 0; tx < tilesPerSide_; ++tx) {
      Aabb& box = tileBoxes_[static_cast<size_t>(tz) * tilesPerSide_ + tx];
      for (int j = 0; j <= kTileQuads; ++j)
        for (int i = 0; i <= kTileQuads; ++i) box.extend(h.position(tx * kTileQuads + i, tz * kTileQuads + j));
      bounds_.extend(box);
      tileDiagonal_ = std::max(tileDiagonal_, box.diagonal());
    }
  }
  // Block boxes (blockBoxes): the samples of each block, its edge rows included.
  for (const int quads : {16, 32}) {
    std::vector<Aabb>& blocks = quads == 16 ? blocks16_ : blocks32_;
    const int perSide = kTileQuads / quads;
    blocks.resize(static_cast<size_t>(tileCount() * perSide * perSide));
    for (int tile = 0; tile < tileCount(); ++tile) {
      const int tx = tile % tilesPerSide_, tz = tile / tilesPerSide_;
      for (int bz = 0; bz < perSide; ++bz)
        for (int bx = 0; bx < perSide; ++bx) {
          Aabb& box = blocks[static_cast<size_t>((tile * perSide + bz) * perSide + bx)];
          for (int j = 0; j <= quads; ++j)
            for (int i = 0; i <= quads; ++i)
              box.extend(h.position(tx * kTileQuads + bx * quads + i, tz * kTileQuads + bz * quads + j));
        }
    }
  }
  blockFacing_ = BlockFacing(h, tilesPerSide_);
  // ε(L): the level-L mesh against every sample it skips. Morphed states lie between level L
  // and L+1 vertex by vertex; the bound is stated for the fully morphed (integer) levels.
  for (int level = 1; level < kLevels; ++level) {
    const int step = 1 << level;
    double worst = 0.0;
    for (int j0 = 0; j0 + step < h.samples(); j0 += step) {
      for (int i0 = 0; i0 + step < h.samples(); i0 += step) {
        const double h00 = h.at(i0, j0), h10 = h.at(i0 + step, j0), h01 = h.at(i0, j0 + step),
                     h11 = h.at(i0 + step, j0 + step);
        for (int j = 0; j <= step; ++j)
          for (int i = 0; i <= step; ++i) {
            const double mesh = quadHeight(h00, h10, h01, h11, static_cast<double>(i) / step, static_cast<double>(j) / step);
            worst = std::max(worst, std::abs(mesh - h.at(i0 + i, j0 + j)));
          }
      }
    }
    levelError_[level] = worst;
  }
}

double Terrain::heightAt(double x, double z) const {
  const Heightfield& h = heightfield_;
  const double fx = std::clamp((x - h.origin().x) / h.spacing(), 0.0, h.samples() - 1.0);
  const double fz = std::clamp((z - h.origin().y) / h.spacing(), 0.0, h.samples() - 1.0);
  const int i = std::min(static_cast<int>(fx), h.samples() - 2), j = std::min(static_cast<int>(fz), h.samples() - 2);
  return quadHeight(h.at(i, j), h.at(i + 1, j), h.at(i, j + 1), h.at(i + 1, j + 1), fx - i, fz - j);
}

glm::dvec3 Terrain::normalAt(double x, double z) const {
  const Heightfield& h = heightfield_;
  const double fx = std::clamp((x - h.origin().x) / h.spacing(), 0.0, h.samples() - 1.0);
  const double fz = std::clamp((z - h.origin().y) / h.spacing(), 0.0, h.samples() - 1.0);
  const int i = std::min(static_cast<int>(fx), h.samples() - 2), j = std::min(static_cast<int>(fz), h.samples() - 2);
  const double u = fx - i, v = fz - j;
  // Barycentric weights of the drawn triangle, as the rasteriser interpolates vertex normals.
  const dvec3 n = v >= u ? (1.0 - v) * h.sampleNormal(i, j) + (v - u) * h.sampleNormal(i, j + 1) + u * h.sampleNormal(i + 1, j + 1)
                         : (1.0 - u) * h.sampleNormal(i, j) + (u - v) * h.sampleNormal(i + 1, j) + v * h.sampleNormal(i + 1, j + 1);
  return glm::normalize(n);
}

TerrainLod Terrain::lodFor(const Camera& camera, int viewportHeight) const {
  if (viewportHeight < 1) throw InputError("terrain LOD: viewport height must be at least 1 pixel");
  TerrainLod lod;
  lod.eye = camera.position;
  lod.errorPixels = settings_.lod_error_pixels;
  // Pixels per metre of vertical error per metre of distance: K = H / (2 tan(fovy / 2)).
  const double pixelsPerRadian = viewportHeight / (2.0 * std::tan(camera.fovy / 2.0));
  const double spacing = heightfield_.spacing();
  double previousEnd = -tileDiagonal_;
  for (int level = 0; level < kLevels - 1; ++level) {
    const double errorDistance = levelError_[level + 1] * pixelsPerRadian / lod.errorPixels;
    lod.morphStart[level] = std::max(errorDistance, previousEnd + tileDiagonal_);
    const double width = std::max(0.3 * lod.morphStart[level], 2.0 * spacing * (1 << level));
    lod.morphEnd[level] = lod.morphStart[level] + width;
    previousEnd = lod.morphEnd[level];
  }
  return lod;
}

std::span<const Aabb> Terrain::blockBoxes(int tile, int level) const {
  const size_t t = static_cast<size_t>(tile);
  switch (blockQuads(level)) {
    case 16: return {blocks16_.data() + 16 * t, 16};
    case 32: return {blocks32_.data() + 4 * t, 4};
    default: return {&tileBoxes_[t], 1};
  }
}

BlockMorph Terrain::blockMorph(int tile, int level, int block, const TerrainLod& lod) const {
  if (level >= kLevels - 1) return BlockMorph::Unmorphed;  // the coarsest level never morphs
  // The vertices' morph factors come from their samples' distances to the LOD's eye (terrain.vert);
  // the block's box holds those samples. Past the ramp's ends (not inside its slack): k is exactly
  // 0 or 1 on the GPU too.
  const Aabb& box = blockBoxes(tile, level)[static_cast<size_t>(block)];
  const double nearest = box.distanceTo(lod.eye);
  const double farthest = glm::length(glm::max(glm::abs(box.min - lod.eye), glm::abs(box.max - lod.eye)));
  if (farthest <= lod.morphStart[static_cast<size_t>(level)]) return BlockMorph::Unmorphed;
  if (nearest >= lod.morphEnd[static_cast<size_t>(level)]) return BlockMorph::Morphed;
  return BlockMorph::Morphing;
}

void Terrain::cellsThatMayFaceAway(int tile, int level, int block, const TerrainLod& lod, const dvec3& toSun,
                                   std::vector<CellSpan>& runs) const {
  if (level < 0 || level >= kLevels || block < 0 || block >= blocksPerTile(level))
    throw Error(fmt::format("terrain: no block {} at level {}", block, level));
  const BlockMorph morph = blockMorph(tile, level, block, lod);
  if (morph == BlockMorph::Morphing && toSun.y > 0.0) return rampCellsThatMayFaceAway(tile, level, block, lod, toSun, runs);
  if (blockFacing_.mayFaceAway(tile, level, block, morph, toSun)) runs.push_back({0, cellsPerBlock(level)});
}

bool Terrain::blockMayFaceAway(int tile, int level, int block, const TerrainLod& lod, const dvec3& toSun) const {
  thread_local std::vector<CellSpan> runs;  // kept from call to call
  runs.clear();
  cellsThatMayFaceAway(tile, level, block, lod, toSun, runs);
  return !runs.empty();
}

int Terrain::tileLevel(int tile, const TerrainLod& lod) const {
  const double distance = tileBoxes_[tile].distanceTo(lod.eye);
  return std::min(static_cast<int>(std::floor(lod.levelAt(distance))), kLevels - 1);
}

std::pair<dvec3, dvec3> Terrain::morphEnds(int tile, int i, int j, int level) const {
  const int tx = tile % tilesPerSide_, tz = tile / tilesPerSide_;
  const int step = 1 << level;
  const int ti = (i / step) % 2 == 1 ? i - step : i;  // odd at this level: slides to i − step
  const int tj = (j / step) % 2 == 1 ? j - step : j;
  return {heightfield_.position(tx * kTileQuads + i, tz * kTileQuads + j), heightfield_.position(tx * kTileQuads + ti, tz * kTileQuads + tj)};
}

glm::dvec3 Terrain::drawnVertex(int tile, int i, int j, int level, const TerrainLod& lod) const {
  const auto [fine, target] = morphEnds(tile, i, j, level);
  const double k = lod.morphFactor(level, glm::distance(fine, lod.eye));
  return fine * (1.0 - k) + target * k;
}

std::vector<TerrainTriangle> Terrain::drawnTriangles(int tile, const TerrainLod& lod) const {
  const int level = tileLevel(tile, lod), step = 1 << level;
  std::vector<TerrainTriangle> triangles;
  triangles.reserve(static_cast<size_t>(2 * (kTileQuads / step) * (kTileQuads / step)));
  for (int j = 0; j < kTileQuads; j += step) {
    for (int i = 0; i < kTileQuads; i += step) {
      const dvec3 v00 = drawnVertex(tile, i, j, level, lod), v10 = drawnVertex(tile, i + step, j, level, lod);
      const dvec3 v01 = drawnVertex(tile, i, j + step, level, lod), v11 = drawnVertex(tile, i + step, j + step, level, lod);
      triangles.push_back({{v00, v01, v11}});
      triangles.push_back({{v00, v11, v10}});
    }
  }
  return triangles;
}

int Terrain::tileOf(double x, double z) const {
  const Heightfield& h = heightfield_;
  const double tileSize = kTileQuads * h.spacing();
  const int tx = std::clamp(static_cast<int>(std::floor((x - h.origin().x) / tileSize)), 0, tilesPerSide_ - 1);
  const int tz = std::clamp(static_cast<int>(std::floor((z - h.origin().y) / tileSize)), 0, tilesPerSide_ - 1);
  return tz * tilesPerSide_ + tx;
}

double Terrain::drawnHeightAt(double x, double z, const TerrainLod& lod) const {
  const Heightfield& h = heightfield_;
  x = std::clamp(x, h.origin().x, h.origin().x + h.size());
  z = std::clamp(z, h.origin().y, h.origin().y + h.size());
  // The drawn triangle whose (x, z) projection holds the point (largest barycentric minimum, so
  // a point on a shared edge takes either side, which agree there).
  double bestHeight = 0.0, bestMinimum = -1e300;
  for (const TerrainTriangle& t : drawnTriangles(tileOf(x, z), lod)) {
    const glm::dvec2 a(t.vertices[0].x, t.vertices[0].z), b(t.vertices[1].x, t.vertices[1].z), c(t.vertices[2].x, t.vertices[2].z);
    const double area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    if (std::abs(area) < 1e-12 * h.spacing() * h.spacing()) continue;  // collapsed by the morph
    const glm::dvec2 p(x, z);
    const double wa = ((b.x - p.x) * (c.y - p.y) - (b.y - p.y) * (c.x - p.x)) / area;
    const double wb = ((c.x - p.x) * (a.y - p.y) - (c.y - p.y) * (a.x - p.x)) / area;
    const double wc = 1.0 - wa - wb;
    const double minimum = std::min({wa, wb, wc});
    if (minimum > bestMinimum) {
      bestMinimum = minimum;
      bestHeight = wa * t.vertices[0].y + wb * t.vertices[1].y + wc * t.vertices[2].y;
    }
  }
  return bestHeight;
}

size_t Terrain::gpuBytes() const {
  size_t bytes = heightfield_.heights().size() * sizeof(float);          // R32F height texture
  bytes += static_cast<size_t>((kTileQuads + 1) * (kTileQuads + 1)) * 2 * sizeof(std::int32_t);  // local grid
  for (int level = 0; level < kLevels; ++level) bytes += tileGridIndices(level).size() * sizeof(std::uint32_t);
  bytes += static_cast<size_t>(tileCount()) * 2 * sizeof(std::int32_t);  // per-tile instance data
  return bytes;
}

double Terrain::gpuBytesPerSquareKilometre() const {
  return static_cast<double>(gpuBytes()) / (heightfield_.size() * heightfield_.size() / 1e6);
}

namespace {

// Triangles of the level-L cells in [0, quads)² of a tile's local grid.
std::vector<std::uint32_t> gridIndices(int level, int quads) {
  if (level < 0 || level >= kLevels) throw Error("terrain: no grid for level " + std::to_string(level));
  const int step = 1 << level, row = kTileQuads + 1;
  std::vector<std::uint32_t> indices;
  auto index = [&](int i, int j) { return static_cast<std::uint32_t>(j * row + i); };
  for (int j = 0; j < quads; j += step) {
    for (int i = 0; i < quads; i += step) {
      // (00, 01, 11) and (00, 11, 10): counter-clockwise seen from above (+y).
      indices.insert(indices.end(), {index(i, j), index(i, j + step), index(i + step, j + step)});
      indices.insert(indices.end(), {index(i, j), index(i + step, j + step), index(i + step, j)});
    }
  }
  return indices;
}

}  // namespace

std::vector<std::uint32_t> tileGridIndices(int level) { return gridIndices(level, kTileQuads); }
std::vector<std::uint32_t> blockGridIndices(int level) { return gridIndices(level, blockQuads(level)); }

}  // namespace forest::terrain
