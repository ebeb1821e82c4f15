#include "forest/terrain/block_facing.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

#include "forest/core/error.hpp"
#include "forest/core/parallel.hpp"
#include "forest/terrain/terrain.hpp"

namespace forest::terrain {
namespace {

using glm::dvec2;
using glm::dvec3;

constexpr int kSlotsPerTile = 4 * 16 + 4 + 1 + 1;  // levels 0–3: 16 blocks, level 4: 4, levels 5 and 6: 1

dvec2 direction(int k) {
  const double angle = 2.0 * std::numbers::pi * k / BlockFacing::kDirections;
  return {std::cos(angle), std::sin(angle)};
}

}  // namespace

int blockQuads(int level) { return std::clamp(2 << level, 16, kTileQuads); }
int blocksPerTile(int level) {
  const int perSide = kTileQuads / blockQuads(level);
  return perSide * perSide;
}

int cellsPerBlock(int level) {
  const int side = blockQuads(level) >> level;
  return side * side;
}

int BlockFacing::slotOf(int level, int block) {
  if (level <= 3) return 16 * level + block;
  return level == 4 ? 64 + block : 63 + level;  // 68, 69
}

BlockFacing::BlockFacing(const Heightfield& h, int tilesPerSide) {
  const int tiles = tilesPerSide * tilesPerSide;
  support_.assign(static_cast<size_t>(tiles) * 2 * kSlotsPerTile * kDirections, -std::numeric_limits<float>::infinity());
  std::array<dvec2, kDirections> directions;
  for (int k = 0; k < kDirections; ++k) directions[static_cast<size_t>(k)] = direction(k);
  const double collapsedArea = 1e-9 * h.spacing() * h.spacing();

  auto tileWork = [&](int tile) {
    const int tx = tile % tilesPerSide, tz = tile / tilesPerSide;
    for (int morphed = 0; morphed < 2; ++morphed)
      for (int level = 0; level < kLevels; ++level) {
        const int step = 1 << level, quads = blockQuads(level), perSide = kTileQuads / quads;
        // The drawn vertex at k = 0 or 1 (terrain.vert, Terrain::drawnVertex); the coarsest level
        // never morphs (TerrainLod::morphFactor).
        auto vertex = [&](int i, int j) {
          const bool slides = morphed == 1 && level < kLevels - 1;
          const int ti = slides && (i / step) % 2 == 1 ? i - step : i, tj = slides && (j / step) % 2 == 1 ? j - step : j;
          return h.position(tx * kTileQuads + ti, tz * kTileQuads + tj);
        };
        for (int j = 0; j < kTileQuads; j += step)
          for (int i = 0; i < kTileQuads; i += step) {
            const size_t slot = (static_cast<size_t>(tile) * 2 + morphed) * kSlotsPerTile + slotOf(level, (j / quads) * perSide + i / quads);
            float* support = &support_[slot * kDirections];
            const dvec3 v00 = vertex(i, j), v10 = vertex(i + step, j), v01 = vertex(i, j + step), v11 = vertex(i + step, j + step);
            // (00, 01, 11) and (00, 11, 10), as tileGridIndices winds them: counter-clockwise from above.
            for (const dvec3 n : {glm::cross(v01 - v00, v11 - v00), glm::cross(v11 - v00, v10 - v00)}) {
              if (glm::length(n) <= collapsedArea) continue;  // collapsed by the morph: no fragments
              // The level's grid triangles, or (morphed) the coarser level's: upward, n_y > 0.
              if (!(n.y > 0.0)) throw Error("BlockFacing: a drawn terrain triangle faces down");
              const dvec2 g(-n.x / n.y, -n.z / n.y);
              for (int k = 0; k < kDirections; ++k) {
                const double s = glm::dot(g, directions[static_cast<size_t>(k)]);
                // Rounded up, so the float never lies below the double.
                support[k] = std::max(support[k], std::nextafter(static_cast<float>(s), std::numeric_limits<float>::infinity()));
              }
            }
          }
      }
  };
  parallelFor(tiles, tileWork);
}

bool BlockFacing::mayFaceAway(int tile, int level, int block, BlockMorph morph, const dvec3& toSun) const {
  if (level < 0 || level >= kLevels || block < 0 || block >= blocksPerTile(level))
    throw Error("BlockFacing: no block " + std::to_string(block) + " at level " + std::to_string(level));
  if (!(toSun.y > 0.0) || morph == BlockMorph::Morphing) return true;
  const size_t slot = (static_cast<size_t>(tile) * 2 + (morph == BlockMorph::Morphed ? 1 : 0)) * kSlotsPerTile + slotOf(level, block);
  const float* support = &support_[slot * kDirections];
  if (support[0] == -std::numeric_limits<float>::infinity()) return false;  // every triangle collapsed
  const dvec2 across(toSun.x, toSun.z);
  const double length = glm::length(across);
  double bound = 0.0;  // ≥ max g·l_xz over the block's slopes
  if (length > 0.0) {
    const double step = 2.0 * std::numbers::pi / kDirections;
    double angle = std::atan2(across.y, across.x);
    if (angle < 0.0) angle += 2.0 * std::numbers::pi;
    const int k = std::min(static_cast<int>(angle / step), kDirections - 1);
    const int next = (k + 1) % kDirections;
    // across/length = α·d_k + β·d_{k+1}: α = sin(θ_{k+1} − θ)/sin Δ, β = sin(θ − θ_k)/sin Δ, both ≥ 0.
    const double alpha = std::max(0.0, std::sin((k + 1) * step - angle) / std::sin(step));
    const double beta = std::max(0.0, std::sin(angle - k * step) / std::sin(step));
    bound = length * (alpha * support[k] + beta * support[next]);
  }
  return !(bound <= toSun.y * (1.0 - BlockFacing::kFacingMargin));
}

}  // namespace forest::terrain
