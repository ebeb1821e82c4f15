// terrain_bench: triangles and time per frame for the default terrain (data/scenes/terrain.toml's
// [terrain]) from ground-level cameras, LOD against full resolution, and GPU bytes per km².
//   build/release/bench/terrain_bench [--gl=auto|egl|osmesa] [--width W --height H] [--frames N]
#include <fmt/format.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>

#include "bench_args.hpp"
#include "forest/core/resources.hpp"
#include "forest/core/scene.hpp"
#include "forest/gl/context.hpp"
#include "forest/render/offscreen_target.hpp"
#include "forest/render/terrain_renderer.hpp"
#include "forest/terrain/terrain.hpp"

namespace {

using namespace forest;
using Clock = std::chrono::steady_clock;

}  // namespace

int main(int argc, char** argv) {
  const bench::BenchArgs options = bench::parseBenchArgs(argc, argv, "terrain_bench", {"auto", 10, 1280, 720});
  const Scene scene = loadScene(resourceDirectory("data") / "scenes" / "terrain.toml");
  auto context = bench::benchContext(options);

  const auto start = Clock::now();
  const terrain::Terrain terrain(*scene.terrain);
  const double generateSeconds = std::chrono::duration<double>(Clock::now() - start).count();
  const render::TerrainRenderer renderer(terrain);
  render::OffscreenTarget target(options.width, options.height);
  const TerrainSettings& s = *scene.terrain;
  std::printf("terrain %.0f m x %.0f m, %d x %d samples (%.3f m), %d tiles; generated in %.2f s\n", s.size, s.size, s.samples,
              s.samples, terrain.heightfield().spacing(), terrain.tileCount(), generateSeconds);
  std::printf("GPU memory: %.2f MiB = %.0f KiB per km^2 (R32F heights + shared grids)\n",
              static_cast<double>(renderer.gpuBytes()) / (1 << 20), terrain.gpuBytesPerSquareKilometre() / 1024.0);
  std::printf("level errors (m):");
  for (int l = 1; l < terrain::kLevels; ++l) std::printf(" %.2f", terrain.levelError(l));
  std::printf("\n\n%-22s | %-10s | %12s %9s | %12s %9s | %s\n", "camera (2 m up)", "error", "LOD tris", "ms/frame",
              "full tris", "ms/frame", "triangle ratio, time ratio");

  SunSettings sun = scene.sun;
  double sumLod = 0, sumFull = 0;
  long long trisLod = 0, trisFull = 0;
  for (double yaw : {0.0, 120.0, 240.0}) {
    for (double errorPixels : {1.0, 2.0, 4.0}) {
      Camera camera = scene.startCamera();
      camera.aspect = static_cast<double>(options.width) / options.height;
      camera.position = {0.0, terrain.heightAt(0.0, 0.0) + 2.0, 0.0};
      camera.yaw = glm::radians(yaw);
      camera.pitch = glm::radians(-3.0);
      // lodFor uses the scene's bound τ; a viewport scaled by τ / errorPixels gives errorPixels.
      const int lodHeight = static_cast<int>(options.height * s.lod_error_pixels / errorPixels);
      const terrain::TerrainLod lod = terrain.lodFor(camera, lodHeight);
      const terrain::TerrainLod full = terrain.lodFor(camera, 1 << 30);  // every tile at level 0
      const std::vector<int> tiles = renderer.tilesInFrustum(camera);
      double ms[2];
      long long triangles[2];
      for (int k = 0; k < 2; ++k) {
        target.bind();
        const terrain::TerrainLod& used = k == 0 ? lod : full;
        triangles[k] = renderer.draw(camera, used, sun, tiles).triangles;  // warm-up
        glFinish();
        const auto t0 = Clock::now();
        for (int f = 0; f < options.frames; ++f) {
          glClearDepth(0.0);
          glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
          renderer.draw(camera, used, sun, tiles);
        }
        glFinish();
        ms[k] = 1e3 * std::chrono::duration<double>(Clock::now() - t0).count() / options.frames;
      }
      std::printf("yaw %5.0f, %3zu tiles    | %5.0f px   | %12lld %9.2f | %12lld %9.2f | %.3f, %.3f\n", yaw, tiles.size(),
                  errorPixels, triangles[0], ms[0], triangles[1], ms[1],
                  static_cast<double>(triangles[0]) / static_cast<double>(triangles[1]), ms[0] / ms[1]);
      sumLod += ms[0];
      sumFull += ms[1];
      trisLod += triangles[0];
      trisFull += triangles[1];
    }
  }
  std::printf("\nall views: LOD/full triangles %.3f, time %.3f (%dx%d, %d frames each)\n",
              static_cast<double>(trisLod) / static_cast<double>(trisFull), sumLod / sumFull, options.width, options.height,
              options.frames);
  return 0;
}
