// forest bench culling: every culling strategy along a ground-level path through a forest scene,
// with per-frame time, triangles, queries and CPU wait, against the oracle (the exact visible set
// from the object-ID buffer). Prints a table and writes JSON.
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <iostream>
#include <map>
#include <memory>
#include <set>

#include "commands.hpp"
#include "forest/core/error.hpp"
#include "forest/core/files.hpp"
#include "forest/core/log.hpp"
#include "forest/core/resources.hpp"
#include "forest/core/scene.hpp"
#include "forest/culling/bvh.hpp"
#include "forest/culling/occlusion_culler.hpp"
#include "forest/gl/context.hpp"
#include "forest/gl/debug.hpp"
#include "forest/render/offscreen_target.hpp"
#include "forest/render/scene_objects.hpp"

namespace forest::app {
namespace {

using Clock = std::chrono::steady_clock;
using culling::CullingStrategy;

struct BenchOptions {
  GlOptions gl;
  std::string scene;
  int frames = 60;
  int width = 640;
  int height = 360;
  int leafSize = 1;
  std::string out = "out/bench-culling.json";
};

struct FrameRecord {
  double milliseconds = 0.0;
  long long triangles = 0;
  int queries = 0;
  int objects = 0;
  double waitMilliseconds = 0.0;
};

}  // namespace

// A walker's path: from the scene's start, 1.4 m per frame along the view, turning 0.8° per frame,
// eye 1.7 m over the ground (or camera.above_ground).
std::vector<Camera> walkPath(const Scene& scene, const terrain::Terrain& terrain, int frames, double aspect) {
  std::vector<Camera> cameras;
  Camera c = scene.startCamera();
  c.aspect = aspect;
  const double above = scene.camera.above_ground.value_or(1.7);
  const Aabb bounds = terrain.bounds();
  for (int f = 0; f < frames; ++f) {
    c.position.x = std::clamp(c.position.x, bounds.min.x + 1.0, bounds.max.x - 1.0);
    c.position.z = std::clamp(c.position.z, bounds.min.z + 1.0, bounds.max.z - 1.0);
    c.position.y = terrain.heightAt(c.position.x, c.position.z) + above;
    cameras.push_back(c);
    const glm::dvec3 forward = directionFromYawPitch(c.yaw, 0.0);
    c.position += 1.4 * forward;
    c.yaw += glm::radians(0.8);
  }
  return cameras;
}

namespace {

int runBenchCulling(const BenchOptions& options) {
  const std::string scenePath =
      options.scene.empty() ? (resourceDirectory("data") / "scenes" / "forest.toml").string() : options.scene;
  const Scene scene = loadScene(scenePath);
  if (!scene.terrain) throw InputError(scenePath + ": bench culling needs a scene with [terrain]");
  if (options.frames < 1 || options.frames > 100000) throw InputError("--frames: expected 1 to 100000");

  gl::ContextOptions contextOptions;
  contextOptions.backend = gl::parseBackend(options.gl.backend);
  auto context = gl::createContext(contextOptions);
  const std::string device = gl::describe(context->info());
  log::info("{}", device);

  const terrain::Terrain terrain(*scene.terrain);
  std::unique_ptr<vegetation::Forest> forest;
  if (scene.vegetation) forest = std::make_unique<vegetation::Forest>(*scene.vegetation, terrain);
  const render::SceneObjects objects(&terrain, forest.get(), scene.props);
  const render::TerrainRenderer terrainLit(terrain), terrainIds(terrain, render::TerrainRenderer::Output::ObjectId, objects.terrainIdBase());
  std::unique_ptr<render::TreeRenderer> treesLit, treeIds;
  if (forest) {
    treesLit = std::make_unique<render::TreeRenderer>(*forest);
    treeIds = std::make_unique<render::TreeRenderer>(*forest, render::TreeRenderer::Output::ObjectId, objects.treeIdBase());
  }
  const render::PropRenderer propsLit(scene.props), propIds(scene.props, render::PropRenderer::Output::ObjectId, objects.propIdBase());
  const culling::Bvh bvh(objects.boxes(), options.leafSize);
  const std::vector<Camera> path = walkPath(scene, terrain, options.frames, static_cast<double>(options.width) / options.height);

  render::OffscreenTarget target(options.width, options.height);
  gl::Texture idTexture(GL_R32UI, options.width, options.height), idDepth(GL_DEPTH_COMPONENT32F, options.width, options.height);
  gl::Framebuffer idFramebuffer;
  idFramebuffer.attach(GL_COLOR_ATTACHMENT0, idTexture);
  idFramebuffer.attach(GL_DEPTH_ATTACHMENT, idDepth);
  auto beginPass = [&](GLuint framebuffer, bool ids) {
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
    glViewport(0, 0, options.width, options.height);
    glClearDepth(0.0);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_GREATER);
    glEnable(GL_CULL_FACE);
    glCullFace(GL_BACK);
    if (ids) {
      const GLuint zero[4] = {0, 0, 0, 0};
      glClearBufferuiv(GL_COLOR, 0, zero);
      glClear(GL_DEPTH_BUFFER_BIT);
    } else {
      const glm::vec3 sky(scene.render.sky_color);
      glClearColor(sky.r, sky.g, sky.b, 1.0f);
      glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    }
  };

  // The oracle: objects with at least one pixel in the ID buffer of the full scene, and the
  // triangles it takes to draw exactly those.
  std::vector<FrameRecord> oracle(path.size());
  {
    culling::OcclusionCuller culler;
    std::vector<std::uint32_t> pixels(static_cast<size_t>(options.width) * options.height);
    for (size_t f = 0; f < path.size(); ++f) {
      const terrain::TerrainLod lod = terrain.lodFor(path[f], options.height);
      beginPass(idFramebuffer.id(), true);
      render::SceneDrawer ids(objects, &terrainIds, treeIds.get(), &propIds, path[f], &lod, 0.0, scene.sun);
      culler.cull(bvh, objects.boxes(), path[f], CullingStrategy::None, ids);
      glGetTextureImage(idTexture.id(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, static_cast<GLsizei>(pixels.size() * 4),
                        pixels.data());
      std::set<std::uint32_t> seen;
      for (std::uint32_t id : pixels)
        if (const std::int64_t o = objects.objectOfId(id); o >= 0) seen.insert(static_cast<std::uint32_t>(o));
      const std::vector<std::uint32_t> visible(seen.begin(), seen.end());
      beginPass(target.framebuffer().id(), false);
      render::SceneDrawer lit(objects, &terrainLit, treesLit.get(), &propsLit, path[f], &lod, 0.0, scene.sun);
      oracle[f].triangles = lit.draw(visible);
      oracle[f].objects = static_cast<int>(visible.size());
    }
  }

  const CullingStrategy strategies[] = {CullingStrategy::None, CullingStrategy::Frustum, CullingStrategy::StopAndWait,
                                        CullingStrategy::Chc};
  nlohmann::ordered_json json;
  json["scene"] = scenePath;
  json["device"] = device;
  json["frames"] = options.frames;
  json["resolution"] = {options.width, options.height};
  json["objects"] = objects.boxes().size();
  json["bvh_nodes"] = bvh.nodes().size();
  std::map<CullingStrategy, std::vector<FrameRecord>> records;
  for (CullingStrategy s : strategies) {
    culling::OcclusionCuller culler;
    std::vector<FrameRecord>& frames = records[s];
    for (size_t f = 0; f < path.size(); ++f) {
      const auto start = Clock::now();
      const terrain::TerrainLod lod = terrain.lodFor(path[f], options.height);
      beginPass(target.framebuffer().id(), false);
      render::SceneDrawer lit(objects, &terrainLit, treesLit.get(), &propsLit, path[f], &lod, 0.0, scene.sun);
      const culling::CullingResult r = culler.cull(bvh, objects.boxes(), path[f], s, lit);
      glFinish();
      frames.push_back({1e3 * std::chrono::duration<double>(Clock::now() - start).count(), r.stats.trianglesDrawn,
                        r.stats.queriesIssued, r.stats.objectsDrawn, r.stats.waitMilliseconds});
    }
    log::info("bench culling: {} done", culling::cullingStrategyName(s));
  }
  if (gl::debugErrorCount() > 0) throw Error(fmt::format("{} GL errors during the benchmark", gl::debugErrorCount()));

  auto summary = [&](const std::vector<FrameRecord>& frames) {
    std::vector<double> ms, tris, queries, wait, drawn;
    for (const FrameRecord& r : frames) {
      ms.push_back(r.milliseconds);
      tris.push_back(static_cast<double>(r.triangles));
      queries.push_back(r.queries);
      wait.push_back(r.waitMilliseconds);
      drawn.push_back(r.objects);
    }
    nlohmann::ordered_json j;
    j["p50_ms"] = percentile(ms, 0.5);
    j["p95_ms"] = percentile(ms, 0.95);
    j["triangles_p50"] = percentile(tris, 0.5);
    j["queries_p50"] = percentile(queries, 0.5);
    j["wait_ms_p50"] = percentile(wait, 0.5);
    j["objects_p50"] = percentile(drawn, 0.5);
    return j;
  };
  std::cout << fmt::format("culling along {} frames at {}x{} ({} objects, BVH {} nodes) — {}\n", options.frames,
                           options.width, options.height, objects.boxes().size(), bvh.nodes().size(), device);
  std::cout << fmt::format("{:<14} {:>9} {:>9} {:>12} {:>9} {:>9} {:>9}\n", "strategy", "p50 ms", "p95 ms", "triangles",
                           "objects", "queries", "wait ms");
  for (CullingStrategy s : strategies) {
    const nlohmann::ordered_json j = summary(records[s]);
    json["strategies"][std::string(culling::cullingStrategyName(s))] = j;
    std::cout << fmt::format("{:<14} {:>9.2f} {:>9.2f} {:>12.0f} {:>9.0f} {:>9.0f} {:>9.2f}\n", culling::cullingStrategyName(s),
                             j["p50_ms"].get<double>(), j["p95_ms"].get<double>(), j["triangles_p50"].get<double>(),
                             j["objects_p50"].get<double>(), j["queries_p50"].get<double>(), j["wait_ms_p50"].get<double>());
  }
  const nlohmann::ordered_json o = summary(oracle);
  json["oracle"] = {{"triangles_p50", o["triangles_p50"]}, {"objects_p50", o["objects_p50"]}};
  std::cout << fmt::format("{:<14} {:>9} {:>9} {:>12.0f} {:>9.0f}\n", "oracle", "", "", o["triangles_p50"].get<double>(),
                           o["objects_p50"].get<double>());
  const double chcTime = json["strategies"]["chc"]["p50_ms"].get<double>();
  const double frustumTime = json["strategies"]["frustum"]["p50_ms"].get<double>();
  const double chcTriangles = json["strategies"]["chc"]["triangles_p50"].get<double>();
  json["ratios"] = {{"chc_over_frustum_time", chcTime / frustumTime},
                    {"chc_over_oracle_triangles", chcTriangles / std::max(1.0, o["triangles_p50"].get<double>())}};
  std::cout << fmt::format("chc / frustum frame time (p50): {:.3f}; chc / oracle triangles (p50): {:.3f}\n",
                           json["ratios"]["chc_over_frustum_time"].get<double>(),
                           json["ratios"]["chc_over_oracle_triangles"].get<double>());
  writeFileAtomic(options.out, json.dump(2) + "\n");
  std::cout << "wrote " << options.out << "\n";
  return 0;
}

}  // namespace

Run addBenchCommand(CLI::App& app) {
  auto options = std::make_shared<BenchOptions>();
  CLI::App* bench = app.add_subcommand("bench", "Benchmarks that print measured numbers and ratios (and write JSON)");
  bench->require_subcommand(1);
  CLI::App* culling = bench->add_subcommand(
      "culling",
      "Every culling strategy (none, frustum, stop-and-wait, chc) along a ground-level walk through a scene:\n"
      "p50/p95 frame time, triangles, queries, CPU wait, and the oracle's triangles (exact visible set)");
  options->gl.add(*culling);
  culling->add_option("--scene", options->scene, "Scene file (default: data/scenes/forest.toml)");
  culling->add_option("--frames", options->frames, "Frames along the walk")->capture_default_str();
  culling->add_option("--width", options->width, "Image width")->check(CLI::Range(16, 8192))->capture_default_str();
  culling->add_option("--height", options->height, "Image height")->check(CLI::Range(16, 8192))->capture_default_str();
  culling->add_option("--leaf-size", options->leafSize, "Objects per BVH leaf")->check(CLI::Range(1, 64))->capture_default_str();
  culling->add_option("--out", options->out, "JSON results")->capture_default_str();
  const Run speedError = addSpeedErrorCommand(*bench);
  return [options, culling, speedError] { return culling->parsed() ? runBenchCulling(*options) : speedError(); };
}

}  // namespace forest::app
