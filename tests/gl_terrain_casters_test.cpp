// Terrain casters by block (the shadow setup's selectTerrainBlocks, Terrain::blockMayFaceAway): a
// backside shadow map draws only the faces turned away from the sun, so a block whose every face
// is turned toward it is left out. Under suns from 5° to 85° over the default forest the shadow
// term is the term with all casters, and a sun steeper than every terrain slope draws no block
// outside a morph ramp.
#include <algorithm>
#include <cmath>
#include <set>
#include <vector>

#include "forest/core/scene.hpp"
#include "forest/render/frame.hpp"
#include "forest/shadows/focus_body.hpp"
#include "forest/terrain/terrain.hpp"
#include "gl_test_support.hpp"
#include "test_paths.hpp"

namespace forest::test {
namespace {

using glm::dvec3;

constexpr int kWidth = 320, kHeight = 240;

class TerrainCastersGl : public GlTest {};

// The steepest slope between neighbouring samples, along x or z. A drawn triangle outside a morph
// ramp is a grid triangle of some level: its slope along x and along z are each an average of such
// differences (its legs run along the grid), so |g| ≤ √2 · this.
double steepestGridSlope(const terrain::Terrain& t) {
  const terrain::Heightfield& h = t.heightfield();
  double steepest = 0.0;
  for (int j = 0; j < h.samples(); ++j)
    for (int i = 0; i < h.samples(); ++i) {
      if (i + 1 < h.samples()) steepest = std::max(steepest, std::abs(static_cast<double>(h.at(i + 1, j)) - h.at(i, j)));
      if (j + 1 < h.samples()) steepest = std::max(steepest, std::abs(static_cast<double>(h.at(i, j + 1)) - h.at(i, j)));
    }
  return steepest / h.spacing();
}

// Triangles of the caster tiles' blocks whose morph factors are not all 0 or all 1: their box
// reaches into the level's ramp [morphStart, morphEnd] (distances to the LOD's eye).
long long rampBlockTriangles(const render::Frame& frame, const terrain::TerrainLod& lod, const std::vector<std::uint32_t>& casters) {
  const terrain::Terrain& t = *frame.terrain();
  std::set<int> tiles;
  for (std::uint32_t o : casters)
    if (o < frame.objects().tileCount()) tiles.insert(static_cast<int>(o));  // tiles come first
  long long triangles = 0;
  for (int tile : tiles) {
    const int level = t.tileLevel(tile, lod);
    if (level == terrain::kLevels - 1) continue;  // never morphs
    for (const Aabb& box : t.blockBoxes(tile, level)) {
      const double nearest = glm::length(glm::max(glm::max(box.min - lod.eye, lod.eye - box.max), dvec3(0.0)));
      const double farthest = glm::length(glm::max(glm::abs(box.min - lod.eye), glm::abs(box.max - lod.eye)));
      if (farthest > lod.morphStart[static_cast<size_t>(level)] && nearest < lod.morphEnd[static_cast<size_t>(level)])
        triangles += static_cast<long long>(terrain::blockGridIndices(level).size() / 3);
    }
  }
  return triangles;
}

TEST_F(TerrainCastersGl, BlocksLeftOutChangeNoShadowAndASteepSunDrawsOnlyRampBlocks) {
  // 40 frame pairs of the engine's own logic: once, on EGL (the backends differ in their context only).
  if (backendUnderTest() != "egl") GTEST_SKIP() << "checked on the egl backend";
  Scene scene = loadScene(std::string(FOREST_REPO_DATA) + "/scenes/forest.toml");
  render::Frame frame(scene, kWidth, kHeight);  // reads scene.sun at every frame
  const terrain::Terrain& t = *frame.terrain();
  const double steepest = steepestGridSlope(t);
  ASSERT_LT(std::sqrt(2.0) * steepest, std::tan(glm::radians(85.0)) * (1.0 - 1e-3)) << "the 85° sun must be steeper than the terrain";
  Camera camera = frame.startCamera();
  camera.aspect = static_cast<double>(kWidth) / kHeight;
  long long terrainAtLowSun = 0, terrainAllAtLowSun = 0, terrainAtSteepSun = 0, terrainAllAtSteepSun = 0;
  for (int v = 0; v < 8; ++v) {
    stepForestView(camera, t, v == 7 ? 9 : v);  // the last view 40 m up
    if (v % kSweepStride != 0) continue;
    for (const double elevation : {5.0, 20.0, 40.0, 60.0, 85.0}) {
      const double e = glm::radians(elevation), a = glm::radians(40.0 + 70.0 * v);
      scene.sun.direction = -dvec3(std::cos(e) * std::cos(a), std::sin(e), std::cos(e) * std::sin(a));
      render::FrameSettings settings;
      settings.method = v % 3 == 0 ? shadows::ShadowMethod::Uniform : v % 3 == 1 ? shadows::ShadowMethod::Lispsm : shadows::ShadowMethod::Tsm;
      settings.shadowMapSize = 1024;
      settings.pcfRadius = v % 3;
      settings.cascades = v % 2 == 0 ? 1 : 3;
      const CasterComparison c = compareSelectedWithAllCasters(frame, camera, 0.5 * v, settings);
      EXPECT_EQ(c.differ, 0) << "view " << v << ", sun " << elevation << "°: " << c.differ << " pixels";
      if (elevation == 5.0) {
        terrainAtLowSun += c.selectedTerrainTriangles;
        terrainAllAtLowSun += c.allTerrainTriangles;
      }
      if (elevation == 85.0) {
        const long long ramp = rampBlockTriangles(frame, t.lodFor(camera, kHeight), c.selected);
        EXPECT_LE(c.selectedTerrainTriangles, ramp * (settings.cascades.value_or(1))) << "view " << v;
        terrainAtSteepSun += c.selectedTerrainTriangles;
        terrainAllAtSteepSun += c.allTerrainTriangles;
      }
    }
  }
  std::printf("[terrain casters] sun 5°: %lld of %lld terrain triangles drawn; sun 85°: %lld of %lld\n", terrainAtLowSun,
              terrainAllAtLowSun, terrainAtSteepSun, terrainAllAtSteepSun);
  EXPECT_GT(terrainAtLowSun, 0);  // a low sun: hills cast, and their blocks are drawn
}

// Receivers by block: a visible terrain tile bounds B by its blocks at the level the eye's LOD
// draws it that meet the view frustum, not by its box. Along the walk's first views, with a high sun,
// B (eq. 4.2 with the visible receivers) lies inside ((V ∩ R) + l) ∩ S computed here from the frame's
// visible set with R = the visible trees' boxes and those blocks (the eye's frustum to its far
// plane holds the frame's, which ends at z_f); in some views that body is more than 1 m lower (or
// higher at its foot) than the one the tiles' boxes give — the bound is tighter, not the same (in
// the others the trees' crowns bound B's top).
TEST_F(TerrainCastersGl, TerrainReceiversAreTheirBlocksInView) {
  if (backendUnderTest() != "egl") GTEST_SKIP() << "checked on the egl backend";
  Scene scene = loadScene(std::string(FOREST_REPO_DATA) + "/scenes/forest.toml");
  scene.sun.direction = -dvec3(0.2, 0.95, 0.1);
  render::Frame frame(scene, kWidth, kHeight);
  const terrain::Terrain& t = *frame.terrain();
  Camera camera = frame.startCamera();
  camera.aspect = static_cast<double>(kWidth) / kHeight;
  Aabb sceneBox;
  for (const Aabb& b : frame.objects().boxes()) sceneBox.extend(b);
  int lower = 0, views = 0;
  for (int v = 0; v < 8; ++v) {
    stepForestView(camera, t, v);
    if (v % kSweepStride != 0) continue;
    render::FrameSettings settings;
    settings.method = shadows::ShadowMethod::Uniform;
    settings.culling = culling::CullingStrategy::Frustum;
    frame.render(camera, 0.0, settings);
    const Aabb byBlocks = visibleReceiverBounds(frame, camera);
    Aabb byTiles;
    for (std::uint32_t o : frame.visibleObjects()) byTiles.extend(frame.objects().boxes()[o]);
    const Aabb expected = shadows::computeFocusBody(camera, scene.sun.direction, sceneBox, byBlocks).bounds();
    const Aabb tiles = shadows::computeFocusBody(camera, scene.sun.direction, sceneBox, byTiles).bounds();
    const Aabb b = frame.shadowSetup(0).body.bounds();
    EXPECT_TRUE(expected.contains(b.min, 1e-6) && expected.contains(b.max, 1e-6))
        << "view " << v << ": B top " << b.max.y << ", bound " << expected.max.y;
    lower += expected.max.y < tiles.max.y - 1.0 || expected.min.y > tiles.min.y + 1.0 ? 1 : 0;
    ++views;
  }
  EXPECT_GT(lower, 0) << "no view of " << views << " bounded lower by blocks than by tiles";
}

}  // namespace
}  // namespace forest::test
