// Terrain blocks the backside shadow map may skip (Terrain::blockMayFaceAway): a block said to
// write nothing has no drawn triangle that faces away from the sun — checked against the drawn
// mesh's CPU twin (Terrain::drawnVertex) in double, at every level, for LOD states whose blocks are
// unmorphed, fully morphed or inside a ramp, under suns all around the sky. (Against the GPU's own
// triangles: TerrainGl.RampBlocksLeftOutOfTheShadowPassWriteNoFragment.)
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <tuple>

#include "forest/core/error.hpp"
#include "forest/terrain/terrain.hpp"

namespace forest::terrain {
namespace {

using glm::dvec3;

TerrainSettings steepTerrain() {
  TerrainSettings s;
  s.size = 500.0;
  s.samples = 257;  // 4 × 4 tiles, 1.953125 m spacing
  s.height_min = -10.0;
  s.height_max = 120.0;
  s.feature_size = 250.0;
  s.seed = 3;
  s.octaves = 8;
  s.ridged = 0.5;
  s.lod_error_pixels = 1.0;
  return s;
}

dvec3 toSun(double elevationDeg, double azimuthDeg) {
  const double e = glm::radians(elevationDeg), a = glm::radians(azimuthDeg);
  return {std::cos(e) * std::cos(a), std::sin(e), std::cos(e) * std::sin(a)};
}

// No morph anywhere, every vertex at its target, and short ramps at random places.
std::vector<TerrainLod> morphStates(const Terrain& t) {
  std::vector<TerrainLod> states;
  TerrainLod lod;
  lod.eye = t.bounds().min;
  lod.morphStart.fill(1e5);
  lod.morphEnd.fill(2e5);
  states.push_back(lod);
  lod.morphStart.fill(0.0);
  lod.morphEnd.fill(1e-6);
  states.push_back(lod);
  std::mt19937 random(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int s = 0; s < 4; ++s) {
    lod.eye = t.bounds().min + dvec3(unit(random), unit(random), unit(random)) * t.bounds().extent();
    for (int level = 0; level < kLevels - 1; ++level) {
      lod.morphStart[static_cast<size_t>(level)] = 300.0 * unit(random);
      lod.morphEnd[static_cast<size_t>(level)] = lod.morphStart[static_cast<size_t>(level)] + 2.0 + 60.0 * unit(random);
    }
    states.push_back(lod);
  }
  return states;
}

TEST(BlockFacing, NoDrawnTriangleOfASkippedBlockFacesAwayFromTheSun) {
  const Terrain t(steepTerrain());
  const double spacing = t.heightfield().spacing();
  long long cases = 0, skipped = 0, backFacing = 0, keptWithoutBackFace = 0;
  std::array<long long, 3> byMorph{};
  for (const TerrainLod& lod : morphStates(t))
    for (int tile = 0; tile < t.tileCount(); ++tile)
      for (int level = 0; level < kLevels; ++level) {
        const int quads = blockQuads(level), perSide = kTileQuads / quads, step = 1 << level;
        for (int block = 0; block < blocksPerTile(level); ++block) {
          ++byMorph[static_cast<size_t>(t.blockMorph(tile, level, block, lod))];
          // The block's drawn triangles, (00, 01, 11) and (00, 11, 10) per cell.
          std::vector<std::tuple<dvec3, dvec3, dvec3>> triangles;
          const int i0 = (block % perSide) * quads, j0 = (block / perSide) * quads;
          for (int j = j0; j < j0 + quads; j += step)
            for (int i = i0; i < i0 + quads; i += step) {
              const dvec3 v00 = t.drawnVertex(tile, i, j, level, lod), v10 = t.drawnVertex(tile, i + step, j, level, lod);
              const dvec3 v01 = t.drawnVertex(tile, i, j + step, level, lod), v11 = t.drawnVertex(tile, i + step, j + step, level, lod);
              triangles.emplace_back(v00, v01, v11);
              triangles.emplace_back(v00, v11, v10);
            }
          for (const double elevation : {3.0, 15.0, 30.0, 45.0, 60.0, 80.0, 90.0})
            for (const double azimuth : {0.0, 37.0, 90.0, 168.0, 225.0, 301.0}) {
              const dvec3 l = toSun(elevation, azimuth);
              const bool mayFaceAway = t.blockMayFaceAway(tile, level, block, lod, l);
              bool away = false;  // beyond rounding: a collapsed triangle has n = 0
              for (const auto& [a, b, c] : triangles) away = away || glm::dot(glm::cross(b - a, c - a), l) < -1e-9 * spacing * spacing;
              ++cases;
              skipped += mayFaceAway ? 0 : 1;
              backFacing += away ? 1 : 0;
              keptWithoutBackFace += mayFaceAway && !away ? 1 : 0;
              ASSERT_TRUE(mayFaceAway || !away) << "tile " << tile << " level " << level << " block " << block
                                                << ": skipped, but a drawn triangle faces away from a sun at elevation "
                                                << elevation << "°, azimuth " << azimuth << "°";
            }
        }
      }
  std::printf("[facing] %lld block × sun cases (blocks unmorphed %lld, morphed %lld, morphing %lld): %lld skipped, "
              "%lld with a back face, %lld kept without one\n",
              cases, byMorph[0], byMorph[1], byMorph[2], skipped, backFacing, keptWithoutBackFace);
  EXPECT_GT(byMorph[0], 0);
  EXPECT_GT(byMorph[1], 0);
  EXPECT_GT(byMorph[2], 0);
  EXPECT_GT(skipped, cases / 4);      // the test is not vacuous: many blocks write nothing
  EXPECT_GT(backFacing, cases / 10);  // and many do
}

// A sun straight overhead faces every triangle of a heightfield (n·l = n_y > 0): no block outside
// a morph ramp is drawn, nor one inside a ramp whose drawn triangles (the CPU twin's) all turn up
// by more than 1% of a full cell's |n| — the GPU's rounding the test allows for is far below that
// (ramp_block_facing.cpp: about 10⁻³ m per vertex here). A sun at the horizon or below: drawn.
TEST(BlockFacing, OverheadSunSkipsEveryBlockOutsideARampAndASunBelowTheHorizonNone) {
  const Terrain t(steepTerrain());
  const double spacing = t.heightfield().spacing();
  int clearRampBlocks = 0;
  for (const TerrainLod& lod : morphStates(t))
    for (int tile = 0; tile < t.tileCount(); ++tile)
      for (int level = 0; level < kLevels; ++level) {
        const int quads = blockQuads(level), perSide = kTileQuads / quads, step = 1 << level;
        const double fullCell = 2.0 * (step * spacing) * (step * spacing);  // |n| of an unmorphed flat cell's triangle
        for (int block = 0; block < blocksPerTile(level); ++block) {
          bool clear = true;  // every drawn triangle turned up by over 1% of a full cell
          const int i0 = (block % perSide) * quads, j0 = (block / perSide) * quads;
          for (int j = j0; j < j0 + quads; j += step)
            for (int i = i0; i < i0 + quads; i += step) {
              const dvec3 v00 = t.drawnVertex(tile, i, j, level, lod), v10 = t.drawnVertex(tile, i + step, j, level, lod);
              const dvec3 v01 = t.drawnVertex(tile, i, j + step, level, lod), v11 = t.drawnVertex(tile, i + step, j + step, level, lod);
              clear = clear && glm::cross(v01 - v00, v11 - v00).y > 0.01 * fullCell && glm::cross(v11 - v00, v10 - v00).y > 0.01 * fullCell;
            }
          const bool ramp = t.blockMorph(tile, level, block, lod) == BlockMorph::Morphing;
          if (!ramp) {
            EXPECT_FALSE(t.blockMayFaceAway(tile, level, block, lod, dvec3(0, 1, 0)));
          } else if (clear) {
            ++clearRampBlocks;
            EXPECT_FALSE(t.blockMayFaceAway(tile, level, block, lod, dvec3(0, 1, 0))) << "tile " << tile << " level " << level << " block " << block;
          }
          EXPECT_TRUE(t.blockMayFaceAway(tile, level, block, lod, dvec3(1, 0, 0)));
          EXPECT_TRUE(t.blockMayFaceAway(tile, level, block, lod, glm::normalize(dvec3(1, -0.2, 0))));
        }
      }
  EXPECT_GT(clearRampBlocks, 0);
  const TerrainLod lod = morphStates(t).front();
  EXPECT_THROW((void)t.blockMayFaceAway(0, 4, 4, lod, dvec3(0, 1, 0)), Error);
  EXPECT_THROW((void)t.blockMayFaceAway(0, kLevels, 0, lod, dvec3(0, 1, 0)), Error);
  EXPECT_THROW((void)t.blockMayFaceAway(0, -1, 0, lod, dvec3(0, 1, 0)), Error);
}

TEST(BlockFacing, BlockGridsCoverTheTileGridOnceAtEveryLevel) {
  for (int level = 0; level < kLevels; ++level) {
    const std::vector<std::uint32_t> tile = tileGridIndices(level), block = blockGridIndices(level);
    EXPECT_EQ(block.size() * static_cast<size_t>(blocksPerTile(level)), tile.size()) << "level " << level;
    EXPECT_EQ(blockQuads(level) * blockQuads(level) * blocksPerTile(level), kTileQuads * kTileQuads);
    // Block 0's triangles are the tile's triangles whose cell lies in [0, blockQuads)².
    std::vector<std::uint32_t> expected;
    const int row = kTileQuads + 1;
    for (size_t k = 0; k < tile.size(); k += 3) {
      const std::uint32_t first = tile[k];  // the cell's (i, j) corner
      if (static_cast<int>(first % row) < blockQuads(level) && static_cast<int>(first / row) < blockQuads(level))
        expected.insert(expected.end(), tile.begin() + static_cast<long>(k), tile.begin() + static_cast<long>(k) + 3);
    }
    EXPECT_EQ(block, expected) << "level " << level;
  }
}

}  // namespace
}  // namespace forest::terrain
