// forest bench scale: the engine from a grove to a landscape. The landscape scene
// (data/scenes/landscape.toml) with 5000 to a million trees at its stand density — the trees on a
// square of the terrain whose area grows with their count ([vegetation] area), centred on each
// camera path's keys — along the landscape walk and flight: start-up, memory, the interval
// between frames, triangles, queries, the culler's CPU time, and at the path's last view the
// casters selected against those the ray-traced truth needs. Writes scale.json, scale.md and
// scale.png (interval against trees).
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>

#include "commands.hpp"
#include "forest/core/camera_path.hpp"
#include "forest/core/error.hpp"
#include "forest/core/files.hpp"
#include "forest/core/log.hpp"
#include "forest/core/plot.hpp"
#include "forest/core/resources.hpp"
#include "forest/gl/context.hpp"
#include "forest/gl/debug.hpp"
#include "forest/truth/frame_truth.hpp"
#include "bench_paths.hpp"
#include "run_output.hpp"

namespace forest::app {
namespace {

using Clock = std::chrono::steady_clock;
using nlohmann::ordered_json;

struct ScaleOptions {
  GlOptions gl;
  std::string scene;
  std::vector<std::string> paths;
  std::vector<int> trees{5000, 50000, 200000, 1000000};
  double fps = 2.0;
  ImageSizeOptions size;
  bool truth = true;
  std::string out = "out/bench-scale";
  FrameOptions frame;
  bool quiet = false;
};

struct ScaleRun {
  std::string path;
  int trees = 0, placed = 0;  // requested, and placed (fewer when they do not fit)
  ordered_json startup, summary, truth;
};

// One path with one tree count: the frames at `fps`, timed as the walkthrough times them (the
// interval from one frame's start to the next's); then the last view against the truth.
ScaleRun runOne(const ScaleOptions& options, const Scene& scene, const CameraPath& path, const std::string& pathName, const gl::Context& context) {
  const int width = options.size.width, height = options.size.height;
  render::Frame frame(scene, width, height);
  render::FrameSettings settings = options.frame.settings(context.info());
  settings.keepShadowTerm = false;
  settings.wholeShadowMap = false;
  const int frames = path.frameCount(options.fps), warmup = std::min(10, frames / 2);
  const std::vector<Camera> cameras = filePath(path, scene, *frame.terrain(), frames, options.fps, static_cast<double>(width) / height);
  ordered_json records = ordered_json::array();
  Clock::time_point previous;
  for (int f = 0; f < frames; ++f) {
    const double time = path.startTime() + f / options.fps;
    const auto start = Clock::now();
    if (f > 0) records.back()["interval_ms"] = std::chrono::duration<double, std::milli>(start - previous).count();
    const render::FrameStats s = frame.render(cameras[static_cast<size_t>(f)], time, settings);
    const double frameMs = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
    records.push_back(frameRecord(f, time, f < warmup, cameras[static_cast<size_t>(f)], path.at(time).yaw_deg, frameMs, s));
    recordPassTimes(frame.takePassTimes(), records);
    previous = start;
    if (!options.quiet) std::cerr << fmt::format("\rbench scale: {} trees along {}: frame {}/{} ", scene.vegetation->count, pathName, f + 1, frames);
  }
  glFinish();
  records.back()["interval_ms"] = std::chrono::duration<double, std::milli>(Clock::now() - previous).count();
  recordPassTimes(frame.drainPassTimes(), records);
  if (!options.quiet) std::cerr << "\n";
  ScaleRun run{pathName, scene.vegetation->count, static_cast<int>(frame.forest()->trees().size()), startupRecord(frame),
               summariseFrames(records, frames - warmup), {}};
  if (options.truth) {  // the last view again, its term kept and the whole map drawn, against the truth
    settings.keepShadowTerm = true;
    settings.wholeShadowMap = true;
    const Camera& last = cameras.back();
    const double time = path.startTime() + (frames - 1) / options.fps;
    const render::FrameStats s = frame.render(last, time, settings);
    truth::TruthOptions truthOptions;
    truthOptions.softRays = 0;
    truthOptions.bandEdges = {200.0};
    const truth::FrameError e = truth::evaluateFrame(frame, s, scene, last, time, truthOptions);
    run.truth = {{"casters_selected", e.casters.selected},           {"casters_needed", e.casters.needed},
                 {"casters_missing", e.casters.missing},             {"triangles_selected", e.casters.selectedTriangles},
                 {"triangles_needed", e.casters.neededTriangles},    {"misclassification", e.misclassification},
                 {"misclassification_beyond_200m", e.bands.back().misclassification}};
  }
  return run;
}

std::string tableOf(const std::vector<ScaleRun>& runs) {
  std::string md =
      "| path | trees | start-up s | heap MiB | bytes/tree | interval p50 / p95 ms | eye / shadow triangles (p50) | queries / draw calls p50 | culler CPU ms p50 | "
      "casters selected / needed | shadow triangles selected / needed | misclassified beyond 200 m |\n"
      "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const ScaleRun& r : runs) {
    const auto p50 = [&](const char* key) { return r.summary[key]["p50"].get<double>(); };
    const bool truth = !r.truth.empty();
    const auto ratio = [](long long a, long long b) { return b > 0 ? fmt::format("{:.2f}×", static_cast<double>(a) / static_cast<double>(b)) : std::string("-"); };
    md += fmt::format("| {} | {} | {:.1f} | {:.0f} | {:.0f} | {:.0f} / {:.0f} | {:.0f} k / {:.0f} k | {:.0f} / {:.0f} | {:.1f} | {} | {} | {} |\n", r.path, r.trees,
                      r.startup["total_ms"].get<double>() / 1e3, r.startup["heap_mib"].get<double>(), r.startup["bytes_per_tree"].get<double>(),
                      p50("interval_ms"), r.summary["interval_ms"]["p95"].get<double>(), p50("triangles_geometry") / 1e3,
                      p50("triangles_shadow") / 1e3, p50("queries"), p50("draw_calls"), p50("culling_cpu_ms"),
                      truth ? fmt::format("{} / {} ({})", r.truth["casters_selected"].get<int>(), r.truth["casters_needed"].get<int>(),
                                          ratio(r.truth["casters_selected"].get<int>(), r.truth["casters_needed"].get<int>()))
                            : "-",
                      truth ? fmt::format("{:.0f} k / {:.0f} k ({})", r.truth["triangles_selected"].get<double>() / 1e3,
                                          r.truth["triangles_needed"].get<double>() / 1e3,
                                          ratio(r.truth["triangles_selected"].get<long long>(), r.truth["triangles_needed"].get<long long>()))
                            : "-",
                      truth ? fmt::format("{:.2f}%", 100.0 * r.truth["misclassification_beyond_200m"].get<double>()) : "-");
  }
  return md;
}

// Interval p50 and p95 against log10(trees), one line per path.
Image8 plotOf(const std::vector<ScaleRun>& runs, const std::vector<std::string>& paths) {
  const glm::vec3 colours[] = {{0.1f, 0.4f, 0.8f}, {0.85f, 0.4f, 0.1f}, {0.2f, 0.6f, 0.2f}, {0.6f, 0.2f, 0.6f}};
  PlotPanel panel{"Interval between frames against trees", "log10 trees", "ms", {}};
  for (size_t k = 0; k < paths.size(); ++k)
    for (const char* percentile : {"p50", "p95"}) {
      PlotSeries series{fmt::format("{} {}", paths[k], percentile), colours[k % 4] * (percentile[1] == '5' ? 1.0f : 0.6f), {}, true};
      for (const ScaleRun& r : runs)
        if (r.path == paths[k]) series.points.emplace_back(std::log10(r.trees), r.summary["interval_ms"][percentile].get<double>());
      panel.series.push_back(std::move(series));
    }
  return plotPanels({panel}, 1, 720, 440);
}

int runBenchScale(const ScaleOptions& options) {
  const std::string scenePath = options.scene.empty() ? (resourceDirectory("data") / "scenes" / "landscape.toml").string() : options.scene;
  const Scene full = loadScene(scenePath);
  if (!full.terrain || !full.vegetation || full.vegetation->grid > 0)
    throw InputError(scenePath + ": bench scale needs a scene with [terrain] and [vegetation] placed by count (not a grid)");
  std::vector<std::string> pathFiles = options.paths;
  if (pathFiles.empty())
    for (const char* name : {"landscape-walk.toml", "landscape-flight.toml"}) pathFiles.push_back((resourceDirectory("data") / "paths" / name).string());
  std::vector<CameraPath> paths;
  std::vector<std::string> names;
  for (const std::string& file : pathFiles) {
    paths.push_back(CameraPath::load(file));
    names.push_back(std::filesystem::path(file).stem().string());
  }
  for (int trees : options.trees)
    if (trees > full.vegetation->count)
      throw InputError(fmt::format("--trees {}: at most the scene's count, {} (the trees thin out to a smaller square, never grow past it)", trees,
                                   full.vegetation->count));
  const std::filesystem::path out = options.out;
  std::filesystem::create_directories(out);
  auto context = options.gl.open(options.size.width, options.size.height);
  const std::string device = gl::describe(context->info());
  std::vector<ScaleRun> runs;
  ordered_json json = {{"device", device}, {"scene", scenePath}, {"fps", options.fps}, {"resolution", {options.size.width, options.size.height}},
                       {"settings", options.frame.json(context->info(), full)}, {"runs", ordered_json::array()}};
  for (size_t k = 0; k < paths.size(); ++k)
    for (int trees : options.trees) {
      runs.push_back(runOne(options, sceneWithTrees(full, paths[k], trees), paths[k], names[k], *context));
      const ScaleRun& r = runs.back();
      json["runs"].push_back({{"path", pathFiles[k]}, {"trees", r.trees}, {"trees_placed", r.placed}, {"startup", r.startup}, {"summary", r.summary}, {"truth", r.truth}});
      std::cerr << fmt::format("  {} trees along {}: {}; interval p50 {:.0f} ms\n", trees, names[k], startupLine(r.startup),
                               r.summary["interval_ms"]["p50"].get<double>());
    }
  if (gl::debugErrorCount() > 0) throw Error(fmt::format("{} GL errors (first: {})", gl::debugErrorCount(), gl::debugErrorMessages().front()));
  const std::string md = "# From a grove to a landscape\n\n" + benchmarkStamp(device) +
                         fmt::format("\n\n`forest bench scale` on {} at {}x{}, {} frames a second of path time: the trees at the scene's stand "
                                     "density on a square around each path whose area grows with their count. Start-up: terrain, trees, "
                                     "objects, GPU upload, BVH; heap: in use after start-up (llvmpipe's GPU buffers included); bytes per tree: the heap added after the terrain, per tree (with the frame's fixed buffers: the slope between rows is the cost of a tree). Casters and "
                                     "misclassification: the path's last view against the ray-traced truth.\n\n",
                                     shownPath(scenePath), options.size.width, options.size.height, options.fps) +
                         tableOf(runs);
  writeFileAtomic(out / "scale.json", json.dump(1) + "\n");
  writeFileAtomic(out / "scale.md", md);
  writeImage(out / "scale.png", plotOf(runs, names));
  std::cout << md << fmt::format("\nwrote {0}/scale.json, {0}/scale.md, {0}/scale.png\n", shownPath(out));
  return 0;
}

}  // namespace

Run addScaleBenchCommand(CLI::App& bench) {
  auto options = std::make_shared<ScaleOptions>();
  CLI::App* command = bench.add_subcommand(
      "scale",
      "From a grove to a landscape: the landscape scene with 5000 to a million trees at its stand density (on a\n"
      "square around each path whose area grows with the count), along the landscape walk and flight: start-up,\n"
      "memory per tree, interval p50/p95, triangles, queries, the culler's CPU time, and at each path's last\n"
      "view the casters selected against those the ray-traced truth needs. Writes scale.json, scale.md, scale.png");
  options->gl.add(*command);
  command->add_option("--scene", options->scene, "Scene file (default: data/scenes/landscape.toml)")->check(CLI::ExistingFile);
  command->add_option("--paths", options->paths, "Camera paths, comma-separated (default: data/paths/landscape-walk.toml and -flight.toml)")
      ->delimiter(',')
      ->check(CLI::ExistingFile);
  command->add_option("--trees", options->trees, "Tree counts, comma-separated (1 to 10^6 each, at most the scene's count)")
      ->delimiter(',')
      ->check(CLI::Range(1, 1000000))
      ->capture_default_str();
  command->add_option("--fps", options->fps, "Frames per second of path time (0.1 to 1000)")->check(CLI::Range(0.1, 1000.0))->capture_default_str();
  options->size.add(*command);
  command->add_flag("--truth,!--no-truth", options->truth, "Each path's last view against the ray-traced truth (the default)");
  command->add_option("--out", options->out, "Output folder (created when missing)")->check(outputFolder())->capture_default_str();
  command->add_flag("--quiet", options->quiet, "No progress line");
  options->frame.add(*command);
  return [options] { return runBenchScale(*options); };
}

}  // namespace forest::app
