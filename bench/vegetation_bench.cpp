// vegetation_bench: mesh and instance memory of the default forest (data/scenes/forest.toml), and
// triangles and milliseconds per frame for its 5000 trees from the walkthrough start — brute force
// at LOD0 against the distance-band LOD, with and without frustum culling of trees.
//   build/release/bench/vegetation_bench [--gl=auto|egl|osmesa] [--frames N]
#include <chrono>
#include <cstdio>
#include <string>

#include "bench_args.hpp"
#include "forest/core/resources.hpp"
#include "forest/core/scene.hpp"
#include "forest/gl/context.hpp"
#include "forest/render/offscreen_target.hpp"
#include "forest/render/tree_renderer.hpp"

namespace {

using namespace forest;
using Clock = std::chrono::steady_clock;

}  // namespace

int main(int argc, char** argv) {
  const bench::BenchArgs args = bench::parseBenchArgs(argc, argv, "vegetation_bench");
  const int frames = args.frames;
  const Scene scene = loadScene(resourceDirectory("data") / "scenes" / "forest.toml");
  auto context = bench::benchContext(args);

  const terrain::Terrain terrain(*scene.terrain);
  auto start = Clock::now();
  VegetationSettings settings = *scene.vegetation;
  const vegetation::Forest forest(settings, terrain);
  const double buildSeconds = std::chrono::duration<double>(Clock::now() - start).count();
  settings.force_lod0 = true;
  const vegetation::Forest forestLod0(settings, terrain);
  const render::TreeRenderer renderer(forest), rendererLod0(forestLod0);
  std::printf("%zu trees in %zu clusters, built in %.2f s (species, LODs, placement)\n", forest.trees().size(),
              forest.clusters().size(), buildSeconds);
  for (const vegetation::SpeciesModel& m : forest.species()) {
    std::printf("  %-9s LOD triangles", std::string(vegetation::speciesName(m.species)).c_str());
    for (int lod = 0; lod < vegetation::kTreeLods; ++lod) std::printf("%s%d", lod == 0 ? " " : " / ", m.lods[lod].triangleCount());
    std::printf("\n");
  }
  std::printf("memory: meshes %.1f KiB on the GPU; instances %.1f KiB on the GPU (64 B each), %.1f KiB on the CPU\n",
              static_cast<double>(renderer.meshBytes()) / 1024.0, static_cast<double>(renderer.instanceBytes()) / 1024.0,
              static_cast<double>(forest.trees().size() * sizeof(vegetation::TreeInstance)) / 1024.0);

  Camera camera = scene.startCamera();
  camera.position.y = terrain.heightAt(camera.position.x, camera.position.z) + scene.camera.above_ground.value_or(1.7);
  render::OffscreenTarget target(scene.render.width, scene.render.height);
  std::vector<std::uint32_t> all(forest.trees().size());
  for (std::uint32_t t = 0; t < all.size(); ++t) all[t] = t;
  const std::vector<std::uint32_t> visible = renderer.treesInFrustum(camera);

  struct Variant {
    const char* name;
    const render::TreeRenderer* renderer;
    const std::vector<std::uint32_t>* trees;
  };
  const Variant variants[] = {{"brute force, LOD0", &rendererLod0, &all},
                              {"all trees, LOD bands", &renderer, &all},
                              {"frustum trees, LOD0", &rendererLod0, &visible},
                              {"frustum trees, LOD bands", &renderer, &visible}};
  double baseMs = 0.0;
  long long baseTriangles = 0;
  std::printf("\n%-30s %8s %12s %10s   %s\n", "trees drawn", "trees", "triangles", "ms/frame", "vs brute force (triangles, time)");
  for (const Variant& v : variants) {
    target.bind();
    glClearDepth(0.0);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_GREATER);
    render::TreeRenderer::Stats stats = v.renderer->draw(camera, *v.trees, 0.0, scene.sun);  // warm-up
    glFinish();
    const auto t0 = Clock::now();
    for (int f = 0; f < frames; ++f) {
      glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
      stats = v.renderer->draw(camera, *v.trees, 0.1 * f, scene.sun);
    }
    glFinish();
    const double ms = 1e3 * std::chrono::duration<double>(Clock::now() - t0).count() / frames;
    if (baseMs == 0.0) {
      baseMs = ms;
      baseTriangles = stats.triangles;
    }
    std::printf("%-30s %8d %12lld %10.2f   %.3f, %.3f\n", v.name, stats.trees, stats.triangles, ms,
                static_cast<double>(stats.triangles) / static_cast<double>(baseTriangles), ms / baseMs);
  }
  std::printf("(%dx%d, %d frames each)\n", scene.render.width, scene.render.height, frames);
  return 0;
}
