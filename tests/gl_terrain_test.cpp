// Terrain on the GPU: the drawn surface equals its CPU twin (Terrain::drawnHeightAt) pixel by
// pixel, morph states included; neighbouring tiles at different levels leave no crack; a tile drawn
// block by block (the shadow pass's terrain casters) is the tile drawn whole; a block inside a morph
// ramp that the shadow setup leaves out writes no fragment with the faces toward the sun culled.
#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "forest/core/camera.hpp"
#include "forest/core/error.hpp"
#include "forest/core/scene.hpp"
#include "forest/gl/objects.hpp"
#include "forest/render/draw_view.hpp"
#include "forest/render/terrain_renderer.hpp"
#include "forest/terrain/terrain.hpp"
#include "gl_test_support.hpp"
#include "test_paths.hpp"

namespace forest::test {
namespace {

using glm::dvec3;

const terrain::Terrain& testTerrain() {
  static const terrain::Terrain terrain([] {
    TerrainSettings s;
    s.size = 500.0;
    s.samples = 257;
    s.height_min = -10.0;
    s.height_max = 90.0;
    s.feature_size = 300.0;
    s.seed = 11;
    s.octaves = 8;  // every field explicit: the tests do not move with the defaults
    s.ridged = 0.4;
    s.lod_error_pixels = 1.0;
    return s;
  }());
  return terrain;
}

// A float colour + depth target (the lit path uses render::OffscreenTarget).
struct FloatTarget {
  gl::Texture color, depth;
  gl::Framebuffer framebuffer;
  int width, height;
  FloatTarget(int w, int h) : color(GL_RGBA32F, w, h), depth(GL_DEPTH_COMPONENT32F, w, h), width(w), height(h) {
    framebuffer.attach(GL_COLOR_ATTACHMENT0, color);
    framebuffer.attach(GL_DEPTH_ATTACHMENT, depth);
  }
  void bindAndClear(const glm::vec4& clear) const {
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer.id());
    glViewport(0, 0, width, height);
    glClearColor(clear.r, clear.g, clear.b, clear.a);
    glClearDepth(0.0);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_GREATER);
    glEnable(GL_CULL_FACE);
    glCullFace(GL_BACK);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  }
  std::vector<glm::vec4> read() const {
    std::vector<glm::vec4> pixels(static_cast<size_t>(width) * height);
    glGetTextureImage(color.id(), 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(pixels.size() * sizeof(glm::vec4)), pixels.data());
    return pixels;
  }
  std::vector<float> readDepth() const {
    std::vector<float> pixels(static_cast<size_t>(width) * height);
    glGetTextureImage(depth.id(), 0, GL_DEPTH_COMPONENT, GL_FLOAT, static_cast<GLsizei>(pixels.size() * sizeof(float)), pixels.data());
    return pixels;
  }
};

Camera lookingDown(const terrain::Terrain& t, double pitchDeg, double heightAbove, double fovyDeg) {
  Camera c;
  c.position = {10.0, t.bounds().max.y + heightAbove, 40.0};
  c.yaw = glm::radians(15.0);
  c.pitch = glm::radians(pitchDeg);
  c.fovy = glm::radians(fovyDeg);
  c.aspect = 4.0 / 3.0;
  c.near = 0.5;
  c.far = 3000.0;
  return c;
}

std::set<int> levelsOf(const terrain::Terrain& t, const terrain::TerrainLod& lod, const std::vector<int>& tiles) {
  std::set<int> levels;
  for (int tile : tiles) levels.insert(t.tileLevel(tile, lod));
  return levels;
}

class TerrainGl : public GlTest {};

TEST_F(TerrainGl, DrawnSurfaceMatchesItsCpuTwinIncludingMorphs) {
  const terrain::Terrain& t = testTerrain();
  const render::TerrainRenderer renderer(t, render::TerrainRenderer::Output::WorldPosition);
  const Camera camera = lookingDown(t, -35.0, 15.0, 60.0);
  // A coarse bound (as for a 40-pixel-high image) brings levels and morphs close to the camera.
  const terrain::TerrainLod lod = t.lodFor(camera, 40);
  const FloatTarget target(320, 240);
  target.bindAndClear(glm::vec4(0.0f));
  const std::vector<int> tiles = renderer.tilesInFrustum(camera);
  renderer.draw(camera, lod, SunSettings{}, tiles);
  const std::vector<glm::vec4> pixels = target.read();
  ASSERT_GE(levelsOf(t, lod, tiles).size(), 2u);

  const double tolerance = 1e-4 * (t.settings().height_max - t.settings().height_min);
  int covered = 0, morphed = 0;
  double worst = 0.0;
  for (size_t p = 0; p < pixels.size(); p += 7) {  // every 7th pixel: about 11 000 points
    if (pixels[p].a == 0.0f) continue;
    const dvec3 world(pixels[p]);
    const double cpu = t.drawnHeightAt(world.x, world.z, lod);
    worst = std::max(worst, std::abs(cpu - world.y));
    ASSERT_NEAR(world.y, cpu, tolerance) << "at (" << world.x << ", " << world.z << ")";
    ++covered;
    const double distance = glm::distance(world, lod.eye);
    const int level = static_cast<int>(std::floor(lod.levelAt(distance)));
    const double k = lod.morphFactor(level, distance);
    morphed += k > 0.05 && k < 0.95 ? 1 : 0;
  }
  EXPECT_GT(covered, 5000);
  EXPECT_GT(morphed, 100);  // partly morphed surface is among the points
  std::printf("[terrain] %d points, %d partly morphed, largest |GPU - CPU| height %.2e m\n", covered, morphed, worst);
}

TEST_F(TerrainGl, NoCracksWhereNeighbouringTilesDifferInLevel) {
  const terrain::Terrain& t = testTerrain();
  const render::TerrainRenderer renderer(t);
  // From above, looking down: the terrain fills the image; black clear colour shows any crack.
  for (int view = 0; view < 3; ++view) {
    Camera camera = lookingDown(t, -72.0 + 6.0 * view, 40.0, 45.0);
    camera.yaw += glm::radians(50.0 * view);
    // Coarse bounds (as for 16…24-pixel-high images) put level changes inside this small view.
    const terrain::TerrainLod lod = t.lodFor(camera, 16 + 4 * view);
    const FloatTarget target(1024, 768);
    target.bindAndClear(glm::vec4(0.0f));
    const std::vector<int> tiles = renderer.tilesInFrustum(camera);
    const render::TerrainRenderer::Stats stats = renderer.draw(camera, lod, SunSettings{}, tiles);
    const std::set<int> levels = levelsOf(t, lod, tiles);
    ASSERT_GE(levels.size(), 2u) << "view " << view << ": the view must show a level change";
    const std::vector<glm::vec4> pixels = target.read();
    int background = 0;
    for (const glm::vec4& p : pixels) background += p.a == 0.0f ? 1 : 0;
    EXPECT_EQ(background, 0) << "view " << view << ": " << background << " background pixels show through ("
                             << stats.tiles << " tiles, levels " << *levels.begin() << "…" << *levels.rbegin() << ")";
  }
}

// Every block of the tiles in view, each at its tile's level (TerrainRenderer::drawBlocks), draws
// exactly what the tiles drawn whole draw: the same world positions and depths, bit for bit, and
// the same triangle count — with morphs and several levels in view.
TEST_F(TerrainGl, TilesDrawnBlockByBlockEqualTheTilesDrawnWhole) {
  // The default forest's 12 × 12 tiles, seen across from a corner: room for levels 0–5.
  const terrain::Terrain t(*loadScene(std::string(FOREST_REPO_DATA) + "/scenes/forest.toml").terrain);
  const render::TerrainRenderer renderer(t, render::TerrainRenderer::Output::WorldPosition);
  Camera camera = lookingDown(t, -12.0, 30.0, 60.0);
  camera.position = dvec3(t.bounds().min.x + 20.0, camera.position.y, t.bounds().min.z + 20.0);
  camera.yaw = glm::radians(-135.0);  // toward +x, +z
  const terrain::TerrainLod lod = t.lodFor(camera, 40);
  const std::vector<int> tiles = renderer.tilesInFrustum(camera);
  const std::set<int> levels = levelsOf(t, lod, tiles);
  // Blocks of 16 quads (levels ≤ 3), 32 (level 4) and 64 (levels 5, 6) all in view.
  ASSERT_LE(*levels.begin(), 3);
  ASSERT_TRUE(levels.contains(4));
  ASSERT_GE(*levels.rbegin(), 5);
  const render::DrawView view = render::DrawView::fromCamera(camera, 0.0, SunSettings{});
  const FloatTarget target(320, 240);
  target.bindAndClear(glm::vec4(0.0f));
  const long long wholeTriangles = renderer.draw(view, lod, tiles).triangles;
  const std::vector<glm::vec4> whole = target.read();
  const std::vector<float> wholeDepth = target.readDepth();
  std::vector<terrain::TileBlock> blocks;
  for (int tile : tiles) {
    const int level = t.tileLevel(tile, lod);
    for (int b = 0; b < terrain::blocksPerTile(level); ++b) blocks.push_back({tile, level, b});
  }
  target.bindAndClear(glm::vec4(0.0f));
  const long long blockTriangles = renderer.drawBlocks(view, lod, blocks).triangles;
  const std::vector<glm::vec4> byBlock = target.read();
  const std::vector<float> byBlockDepth = target.readDepth();
  EXPECT_EQ(blockTriangles, wholeTriangles);
  int covered = 0, differ = 0;
  for (size_t p = 0; p < whole.size(); ++p) {
    covered += whole[p].a != 0.0f ? 1 : 0;
    differ += whole[p] != byBlock[p] || wholeDepth[p] != byBlockDepth[p] ? 1 : 0;
  }
  EXPECT_GT(covered, 320 * 240 / 2);
  EXPECT_EQ(differ, 0) << differ << " of " << whole.size() << " pixels differ";
  // Each block as two spans of its cells (cut at a cell that varies from block to block: the
  // multi-draw of blocks drawn in part) gives the same image and triangles again.
  std::vector<terrain::TileBlock> halves;
  for (size_t i = 0; i < blocks.size(); ++i) {
    const int cells = terrain::cellsPerBlock(blocks[i].level), cut = 1 + static_cast<int>(i) % (cells - 1);
    halves.push_back({blocks[i].tile, blocks[i].level, blocks[i].block, {0, cut}});
    halves.push_back({blocks[i].tile, blocks[i].level, blocks[i].block, {cut, cells}});
  }
  target.bindAndClear(glm::vec4(0.0f));
  EXPECT_EQ(renderer.drawBlocks(view, lod, halves).triangles, wholeTriangles);
  const std::vector<glm::vec4> byHalves = target.read();
  const std::vector<float> byHalvesDepth = target.readDepth();
  int differHalves = 0;
  for (size_t p = 0; p < whole.size(); ++p) differHalves += whole[p] != byHalves[p] || wholeDepth[p] != byHalvesDepth[p] ? 1 : 0;
  EXPECT_EQ(differHalves, 0) << differHalves << " of " << whole.size() << " pixels differ when blocks are drawn in two spans";
  // Every other block: each drawn point lies over one of the blocks asked for (its box's x, z).
  std::vector<Aabb> footprints;
  std::vector<terrain::TileBlock> some;
  for (size_t i = 0; i < blocks.size(); i += 2) {
    some.push_back(blocks[i]);
    footprints.push_back(t.blockBoxes(blocks[i].tile, blocks[i].level)[static_cast<size_t>(blocks[i].block)]);
  }
  target.bindAndClear(glm::vec4(0.0f));
  renderer.drawBlocks(view, lod, some);
  int someCovered = 0, outside = 0;
  for (const glm::vec4& p : target.read()) {
    if (p.a == 0.0f) continue;
    ++someCovered;
    const bool over = std::any_of(footprints.begin(), footprints.end(), [&](const Aabb& b) {
      return p.x >= b.min.x - 1e-3 && p.x <= b.max.x + 1e-3 && p.z >= b.min.z - 1e-3 && p.z <= b.max.z + 1e-3;
    });
    outside += over ? 0 : 1;
  }
  EXPECT_GT(someCovered, covered / 5);
  EXPECT_EQ(outside, 0) << outside << " of " << someCovered << " pixels lie outside the blocks drawn";
  EXPECT_THROW(renderer.drawBlocks(view, lod, std::vector<terrain::TileBlock>{{tiles.front(), 6, 1}}), Error);
  EXPECT_THROW(renderer.drawBlocks(view, lod, std::vector<terrain::TileBlock>{{tiles.front(), 0, 1, {5, 5}}}), Error);
  EXPECT_THROW(renderer.drawBlocks(view, lod, std::vector<terrain::TileBlock>{{tiles.front(), 0, 1, {-1, 5}}}), Error);
}

// Terrain::cellsThatMayFaceAway inside a morph ramp decides triangle by triangle at the frame's
// morph factors, with a bound on the GPU's rounding. Checked against the GPU itself: every cell it
// leaves out — a whole ramp block, or the cells between its runs — drawn alone (terrain.vert, the
// LOD's own morph) by an orthographic view along the light with the faces toward the sun culled —
// what the backside shadow pass keeps — passes no sample, at ~6 cm per pixel; LOD states of real
// cameras and random ramps, suns all around.
TEST_F(TerrainGl, RampBlocksLeftOutOfTheShadowPassWriteNoFragment) {
  const terrain::Terrain& t = testTerrain();
  const render::TerrainRenderer renderer(t, render::TerrainRenderer::Output::WorldPosition);
  std::vector<terrain::TerrainLod> lods;
  for (int c = 0; c < 3; ++c) {
    Camera camera = lookingDown(t, -20.0, 5.0 + 10.0 * c, 60.0);
    camera.position.x += 120.0 * c;
    lods.push_back(t.lodFor(camera, 60 << c));
  }
  std::mt19937 random(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int s = 0; s < 2; ++s) {
    terrain::TerrainLod lod = lods.front();
    lod.eye = t.bounds().min + dvec3(unit(random), unit(random), unit(random)) * t.bounds().extent();
    for (int level = 0; level < terrain::kLevels - 1; ++level) {
      lod.morphStart[static_cast<size_t>(level)] = 40.0 + 80.0 * level + 40.0 * unit(random);
      lod.morphEnd[static_cast<size_t>(level)] = lod.morphStart[static_cast<size_t>(level)] + 3.0 + 30.0 * unit(random);
    }
    lods.push_back(lod);
  }
  constexpr int kSide = 512;
  const FloatTarget target(kSide, kSide);
  target.bindAndClear(glm::vec4(0.0f));
  glDisable(GL_DEPTH_TEST);
  glFrontFace(GL_CCW);
  glCullFace(GL_FRONT);
  gl::Query samples(GL_SAMPLES_PASSED);
  int rampBlocks = 0, leftOut = 0, keptWithSamples = 0, keptInPart = 0;
  std::vector<terrain::CellSpan> runs;
  for (const terrain::TerrainLod& lod : lods)
    for (const double elevation : {8.0, 30.0, 60.0, 85.0})
      for (const double azimuth : {20.0, 150.0, 260.0}) {
        const double e = glm::radians(elevation), a = glm::radians(azimuth);
        const dvec3 toSun(std::cos(e) * std::cos(a), std::sin(e), std::cos(e) * std::sin(a));
        for (int tile = 0; tile < t.tileCount(); ++tile) {
          const int level = t.tileLevel(tile, lod);
          for (int b = 0; b < terrain::blocksPerTile(level); ++b) {
            if (t.blockMorph(tile, level, b, lod) != terrain::BlockMorph::Morphing) continue;
            ++rampBlocks;
            runs.clear();
            t.cellsThatMayFaceAway(tile, level, b, lod, toSun, runs);
            const bool mayFaceAway = !runs.empty();
            // Looking along the light at the block's box, which fills the image.
            const Aabb& box = t.blockBoxes(tile, level)[static_cast<size_t>(b)];
            const double radius = 0.5 * glm::length(box.extent()) + 1.0;
            render::DrawView view;
            view.origin = lod.eye;
            const dvec3 centre = box.centre() - lod.eye;
            const dvec3 up = std::abs(toSun.y) > 0.9 ? dvec3(1, 0, 0) : dvec3(0, 1, 0);
            view.viewProjectionRelative = glm::ortho(-radius, radius, -radius, radius, 0.0, 4.0 * radius) *
                                          glm::lookAt(centre + 2.0 * radius * toSun, centre, up);
            auto samplesOf = [&](const std::vector<terrain::TileBlock>& drawn) {
              glBeginQuery(GL_SAMPLES_PASSED, samples.id());
              renderer.drawBlocks(view, lod, drawn);
              glEndQuery(GL_SAMPLES_PASSED);
              GLuint passed = 0;
              glGetQueryObjectuiv(samples.id(), GL_QUERY_RESULT, &passed);
              return passed;
            };
            const GLuint passed = samplesOf({{tile, level, b}});
            // The cells between the runs (a block kept in part) write nothing either.
            std::vector<terrain::TileBlock> gaps;
            int from = 0;
            for (const terrain::CellSpan& run : runs) {
              if (run.first > from) gaps.push_back({tile, level, b, {from, run.first}});
              from = run.end;
            }
            if (mayFaceAway && from < terrain::cellsPerBlock(level)) gaps.push_back({tile, level, b, {from, terrain::cellsPerBlock(level)}});
            if (!gaps.empty()) {
              ++keptInPart;
              const GLuint gapSamples = samplesOf(gaps);
              ASSERT_EQ(gapSamples, 0u) << "tile " << tile << " level " << level << " block " << b << ", sun at " << elevation << "°, "
                                        << azimuth << "°: " << gaps.size() << " spans of cells left out write " << gapSamples
                                        << " samples of faces turned away from the sun";
            }
            leftOut += mayFaceAway ? 0 : 1;
            keptWithSamples += mayFaceAway && passed > 0 ? 1 : 0;
            ASSERT_TRUE(mayFaceAway || passed == 0)
                << "tile " << tile << " level " << level << " block " << b << ", sun at " << elevation << "°, " << azimuth
                << "°: left out, but " << passed << " samples of faces turned away from the sun";
          }
        }
      }
  glCullFace(GL_BACK);
  std::printf("[ramp blocks] %d ramp block × sun cases: %d left out, %d kept that the GPU draws back faces of, %d kept in part\n",
              rampBlocks, leftOut, keptWithSamples, keptInPart);
  EXPECT_GT(rampBlocks, 1000);
  // Not vacuous: many ramp blocks are left out, and the view does show back faces where there are.
  EXPECT_GT(leftOut, rampBlocks / 10);
  EXPECT_GT(keptWithSamples, rampBlocks / 10);
  EXPECT_GT(keptInPart, rampBlocks / 20);
}

}  // namespace
}  // namespace forest::test
