// Terrain on the GPU: the drawn surface equals its CPU twin (Terrain::drawnHeightAt) pixel by
// pixel, morph states included; neighbouring tiles at different levels leave no crack.
#include <algorithm>
#include <cmath>
#include <set>
#include <vector>

#include "forest/core/camera.hpp"
#include "forest/gl/objects.hpp"
#include "forest/render/terrain_renderer.hpp"
#include "forest/terrain/terrain.hpp"
#include "gl_test_support.hpp"

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

}  // namespace
}  // namespace forest::test
