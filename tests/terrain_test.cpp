// Terrain on the CPU: determinism, exact tile boxes, heightAt/normalAt on the drawn triangle
// split, and the LOD's promises — every morph state inside its tile box, neighbouring tiles at
// most one level apart and drawing identical vertices along their shared edge (no cracks), the
// error bound in pixels.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <random>
#include <set>
#include <span>

#include "forest/core/error.hpp"
#include "forest/terrain/terrain.hpp"

namespace forest::terrain {
namespace {

using glm::dvec3;

TerrainSettings smallTerrain(std::uint64_t seed = 1) {
  TerrainSettings s;
  s.size = 500.0;
  s.samples = 257;  // 4 × 4 tiles, 1.953125 m spacing
  s.height_min = -10.0;
  s.height_max = 90.0;
  s.feature_size = 300.0;
  s.seed = seed;
  s.octaves = 8;  // every field explicit: the tests do not move with the defaults
  s.ridged = 0.4;
  s.lod_error_pixels = 1.0;
  return s;
}

const Terrain& sharedTerrain() {
  static const Terrain terrain(smallTerrain());
  return terrain;
}

TEST(Heightfield, SameSeedIsBitIdenticalOtherSeedDiffers) {
  const Heightfield a(smallTerrain(7)), b(smallTerrain(7)), c(smallTerrain(8));
  ASSERT_EQ(a.heights().size(), b.heights().size());
  EXPECT_EQ(std::memcmp(a.heights().data(), b.heights().data(), a.heights().size() * sizeof(float)), 0);
  size_t differ = 0;
  for (size_t i = 0; i < a.heights().size(); ++i) differ += a.heights()[i] != c.heights()[i] ? 1 : 0;
  EXPECT_GT(differ, a.heights().size() * 9 / 10);
}

TEST(Heightfield, HeightsFillTheRangeExactly) {
  const Heightfield h(smallTerrain());
  const auto [lo, hi] = std::minmax_element(h.heights().begin(), h.heights().end());
  EXPECT_EQ(*lo, -10.0f);
  EXPECT_EQ(*hi, 90.0f);
  EXPECT_DOUBLE_EQ(h.spacing(), 500.0 / 256.0);
  EXPECT_EQ(h.position(0, 0), dvec3(-250.0, h.at(0, 0), -250.0));
}

TEST(Heightfield, InvalidSettingsAreRefused) {
  TerrainSettings s = smallTerrain();
  s.samples = 100;  // 99 is not a multiple of 64
  EXPECT_THROW(Heightfield{s}, InputError);
  s = smallTerrain();
  s.octaves = 17;
  EXPECT_THROW(Heightfield{s}, InputError);
}

TEST(Terrain, SixteenKilometresAreConfigurable) {
  TerrainSettings s = smallTerrain();
  s.size = 16000.0;
  s.samples = 513;  // 31.25 m spacing, 8 × 8 tiles of 2 km
  const Terrain t(s);
  EXPECT_EQ(t.tilesPerSide(), 8);
  EXPECT_DOUBLE_EQ(t.bounds().min.x, -8000.0);
  EXPECT_DOUBLE_EQ(t.bounds().max.z, 8000.0);
  EXPECT_GE(t.heightAt(1234.5, -777.0), s.height_min);
  EXPECT_LE(t.heightAt(1234.5, -777.0), s.height_max);
}

TEST(Terrain, TileBoxesAreExactOverTheirSamples) {
  const Terrain& t = sharedTerrain();
  ASSERT_EQ(t.tilesPerSide(), 4);
  const Heightfield& h = t.heightfield();
  for (int tile = 0; tile < t.tileCount(); ++tile) {
    const int tx = tile % 4, tz = tile / 4;
    float lo = 1e30f, hi = -1e30f;
    for (int j = 0; j <= kTileQuads; ++j)
      for (int i = 0; i <= kTileQuads; ++i) {
        lo = std::min(lo, h.at(tx * 64 + i, tz * 64 + j));
        hi = std::max(hi, h.at(tx * 64 + i, tz * 64 + j));
      }
    const Aabb& box = t.tileBox(tile);
    EXPECT_EQ(box.min.y, lo);  // tight: a sample sits on each face
    EXPECT_EQ(box.max.y, hi);
    EXPECT_DOUBLE_EQ(box.min.x, -250.0 + tx * 125.0);
    EXPECT_DOUBLE_EQ(box.max.z, -250.0 + (tz + 1) * 125.0);
  }
}

TEST(Terrain, HeightAtIsTheDrawnTriangleSplit) {
  const Terrain& t = sharedTerrain();
  const Heightfield& h = t.heightfield();
  // At samples: the sample.
  for (int k = 0; k < 50; ++k) {
    const int i = (k * 37) % 257, j = (k * 91) % 257;
    EXPECT_EQ(t.heightAt(h.position(i, j).x, h.position(i, j).z), static_cast<double>(h.at(i, j)));
  }
  // Inside a quad: the plane of triangle (00, 01, 11) where v ≥ u, (00, 11, 10) where u ≥ v —
  // checked against the plane through the three corner points, not the formula in the code.
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int k = 0; k < 2000; ++k) {
    const int i = static_cast<int>(unit(rng) * 256), j = static_cast<int>(unit(rng) * 256);
    const double u = unit(rng), v = unit(rng);
    const dvec3 p00 = h.position(i, j), p11 = h.position(i + 1, j + 1);
    const dvec3 other = v >= u ? h.position(i, j + 1) : h.position(i + 1, j);
    const dvec3 n = glm::cross(other - p00, p11 - p00);
    const double x = p00.x + u * h.spacing(), z = p00.z + v * h.spacing();
    const double planeY = p00.y - (n.x * (x - p00.x) + n.z * (z - p00.z)) / n.y;
    EXPECT_NEAR(t.heightAt(x, z), planeY, 1e-9);
  }
}

TEST(Terrain, NormalAtInterpolatesVertexNormals) {
  const Terrain& t = sharedTerrain();
  const Heightfield& h = t.heightfield();
  const dvec3 p = h.position(100, 120);
  EXPECT_NEAR(glm::distance(t.normalAt(p.x, p.z), h.sampleNormal(100, 120)), 0.0, 1e-12);
  const dvec3 mid = 0.5 * (h.position(100, 120) + h.position(101, 121));  // on the diagonal
  const dvec3 expected = glm::normalize(h.sampleNormal(100, 120) + h.sampleNormal(101, 121));
  EXPECT_NEAR(glm::distance(t.normalAt(mid.x, mid.z), expected), 0.0, 1e-12);
  EXPECT_NEAR(glm::length(t.normalAt(3.7, -8.1)), 1.0, 1e-12);
  EXPECT_GT(t.normalAt(3.7, -8.1).y, 0.0);
}

Camera groundCamera(const Terrain& t, double x, double z, double yawDeg, double heightAboveGround) {
  Camera c;
  c.position = {x, t.heightAt(x, z) + heightAboveGround, z};
  c.yaw = glm::radians(yawDeg);
  c.pitch = glm::radians(-10.0);
  c.far = 5000.0;
  return c;
}

// LOD states to test: coarse error bounds put level changes and morphs close to the camera.
std::vector<TerrainLod> lodStates(const Terrain& t) {
  std::vector<TerrainLod> states;
  for (double errorPixels : {1.0, 8.0, 64.0}) {
    for (int k = 0; k < 4; ++k) {
      const Camera c = groundCamera(t, -200.0 + 130.0 * k, 150.0 - 90.0 * k, 40.0 * k, 2.0 + 20.0 * k);
      // A viewport τ times lower moves the levels as an error bound τ times larger would.
      states.push_back(t.lodFor(c, static_cast<int>(720 / errorPixels)));
    }
  }
  return states;
}

TEST(TerrainLod, EveryMorphStateStaysInsideItsTileBox) {
  const Terrain& t = sharedTerrain();
  int morphing = 0;
  for (const TerrainLod& lod : lodStates(t)) {
    for (int tile = 0; tile < t.tileCount(); ++tile) {
      const Aabb& box = t.tileBox(tile);
      for (int level = 0; level < kLevels; ++level) {  // every level, not only the chosen one
        const int step = 1 << level;
        for (int j = 0; j <= kTileQuads; j += step)
          for (int i = 0; i <= kTileQuads; i += step) {
            const dvec3 v = t.drawnVertex(tile, i, j, level, lod);
            ASSERT_TRUE(box.contains(v, 1e-9)) << "tile " << tile << " level " << level << " (" << i << ", " << j << ")";
          }
      }
      const int level = t.tileLevel(tile, lod);
      const double k = lod.morphFactor(level, glm::distance(t.heightfield().position(tile % 4 * 64 + 1, tile / 4 * 64 + 1), lod.eye));
      morphing += k > 0.0 && k < 1.0 ? 1 : 0;
    }
  }
  EXPECT_GT(morphing, 0);  // the states include partly morphed tiles
}

// The block boxes a tile's occlusion query draws at a level (Terrain::blockBoxes) hold what that
// level draws, in every morph state: each drawn cell's four (morphed) corners lie in one block box,
// so the cell's two triangles do. And they are tighter than the tile box where the tile is not flat.
TEST(TerrainLod, EveryDrawnCellLiesInOneBlockBoxOfItsLevel) {
  const Terrain& t = sharedTerrain();
  double blockVolume = 0.0, tileVolume = 0.0;
  std::vector<TerrainLod> states = lodStates(t);
  // And states that morph every level everywhere: ramps over the whole terrain (k from 0 to ~1
  // across it), and ramps already ended (k = 1: every odd vertex at its target).
  for (const double end : {2.0 * t.heightfield().size(), 1e-6}) {
    TerrainLod all = states.front();
    all.eye = t.bounds().min;
    all.morphStart.fill(0.0);
    all.morphEnd.fill(end);
    states.push_back(all);
  }
  for (const TerrainLod& lod : states) {
    for (int tile = 0; tile < t.tileCount(); ++tile) {
      for (int level = 0; level < kLevels; ++level) {
        const std::span<const Aabb> blocks = t.blockBoxes(tile, level);
        const int step = 1 << level;
        for (int j = 0; j < kTileQuads; j += step)
          for (int i = 0; i < kTileQuads; i += step) {
            const dvec3 corners[4] = {t.drawnVertex(tile, i, j, level, lod), t.drawnVertex(tile, i + step, j, level, lod),
                                      t.drawnVertex(tile, i, j + step, level, lod), t.drawnVertex(tile, i + step, j + step, level, lod)};
            const bool inOne = std::any_of(blocks.begin(), blocks.end(), [&](const Aabb& b) {
              return std::all_of(std::begin(corners), std::end(corners), [&](const dvec3& c) { return b.contains(c, 1e-9); });
            });
            ASSERT_TRUE(inOne) << "tile " << tile << " level " << level << " cell (" << i << ", " << j << ")";
          }
        if (level == 0 && &lod == &states.front()) {
          for (const Aabb& b : blocks) blockVolume += b.extent().x * b.extent().y * b.extent().z;
          const Aabb& box = t.tileBox(tile);
          tileVolume += box.extent().x * box.extent().y * box.extent().z;
        }
      }
    }
  }
  EXPECT_LT(blockVolume, 0.8 * tileVolume);
}

TEST(TerrainLod, NeighboursDrawTheSameEdgeVertices) {
  const Terrain& t = sharedTerrain();
  int levelChanges = 0;
  for (const TerrainLod& lod : lodStates(t)) {
    for (int tile = 0; tile < t.tileCount(); ++tile) {
      const int tx = tile % 4, tz = tile / 4;
      for (int direction = 0; direction < 2; ++direction) {  // right and far neighbour
        const int neighbour = direction == 0 ? (tx + 1 < 4 ? tile + 1 : -1) : (tz + 1 < 4 ? tile + 4 : -1);
        if (neighbour < 0) continue;
        const int la = t.tileLevel(tile, lod), lb = t.tileLevel(neighbour, lod);
        ASSERT_LE(std::abs(la - lb), 1) << "tiles " << tile << ", " << neighbour;
        levelChanges += la != lb ? 1 : 0;
        // The distinct drawn points along the shared edge, from each side.
        auto edge = [&](int which, int level, bool near) {
          std::set<std::array<double, 3>> points;
          const int step = 1 << level;
          for (int s = 0; s <= kTileQuads; s += step) {
            const int edgeIndex = near ? kTileQuads : 0;
            const dvec3 v = direction == 0 ? t.drawnVertex(which, edgeIndex, s, level, lod)
                                           : t.drawnVertex(which, s, edgeIndex, level, lod);
            points.insert({v.x, v.y, v.z});
          }
          return points;
        };
        EXPECT_EQ(edge(tile, la, true), edge(neighbour, lb, false)) << "tiles " << tile << " (level " << la << ") and "
                                                                    << neighbour << " (level " << lb << ")";
      }
    }
  }
  EXPECT_GT(levelChanges, 10);  // the states do put neighbours at different levels
}

TEST(TerrainLod, LevelsKeepTheStatedScreenSpaceError) {
  // The tile level's fully morphed error ε(L+1), projected at the tile's nearest distance,
  // stays under the bound: ε(L+1) · K / d ≤ τ wherever a tile starts morphing to L+1.
  const Terrain& t = sharedTerrain();
  for (int level = 1; level < kLevels; ++level) EXPECT_GE(t.levelError(level), t.levelError(level - 1));
  EXPECT_EQ(t.levelError(0), 0.0);
  const Camera c = groundCamera(t, 0, 0, 0, 2.0);
  const int height = 720;
  const TerrainLod lod = t.lodFor(c, height);
  const double k = height / (2.0 * std::tan(c.fovy / 2.0));
  for (int level = 0; level < kLevels - 1; ++level) {
    EXPECT_LE(t.levelError(level + 1) * k / lod.morphStart[level], lod.errorPixels * (1.0 + 1e-12)) << level;
    EXPECT_GT(lod.morphEnd[level], lod.morphStart[level]);
    if (level + 1 < kLevels - 1) {
      EXPECT_GE(lod.morphStart[level + 1], lod.morphEnd[level]);
    }
  }
}

TEST(TerrainLod, FullResolutionWhenTheBoundIsTight) {
  const Terrain& t = sharedTerrain();
  const Camera c = groundCamera(t, 0, 0, 0, 2.0);
  const TerrainLod lod = t.lodFor(c, 100000);  // a huge viewport: every level is too coarse
  for (int tile = 0; tile < t.tileCount(); ++tile) EXPECT_EQ(t.tileLevel(tile, lod), 0);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> coordinate(-249.0, 249.0);
  for (int k = 0; k < 200; ++k) {
    const double x = coordinate(rng), z = coordinate(rng);
    EXPECT_NEAR(t.drawnHeightAt(x, z, lod), t.heightAt(x, z), 1e-9);
  }
}

TEST(Terrain, GpuMemoryIsStatedPerSquareKilometre) {
  const Terrain& t = sharedTerrain();
  // 257² float heights + grid, indices and instances: about 1 MiB per km² at 1.95 m spacing.
  EXPECT_GT(t.gpuBytes(), 257u * 257u * 4u);
  EXPECT_LT(t.gpuBytes(), 257u * 257u * 4u + 200000u);
  EXPECT_NEAR(t.gpuBytesPerSquareKilometre(), static_cast<double>(t.gpuBytes()) / 0.25, 1e-6);
}

}  // namespace
}  // namespace forest::terrain
