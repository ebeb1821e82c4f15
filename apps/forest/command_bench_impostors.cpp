// forest bench impostors: what far trees as impostors cost in image and shadows, and what they save
// (issue "Far trees as impostors"). The landscape with --trees trees at its stand density around each
// path (as bench scale places them); at each path's last view, three frames of the same view: every
// tree a mesh at its LOD (the all-mesh frame), far trees as impostors, and every tree at LOD0. Over
// the pixels beyond the switch distance: the impostor frame's difference to the all-mesh frame, and —
// the error the engine already accepts — the LOD chain's difference to all-LOD0 (SSIM, mean |Δ|,
// share off by more than 8/255); the truth's misclassification beyond 200 m with impostor and with
// mesh casters; triangles and frame times (alternating); and a slow dolly back across the switch
// distance: the mean per-pixel change between frames with the switch and with it off. Writes
// impostors.json, impostors.md and each view's three images.
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
#include "forest/core/image_difference.hpp"
#include "forest/core/resources.hpp"
#include "forest/core/statistics.hpp"
#include "forest/gl/context.hpp"
#include "forest/gl/debug.hpp"
#include "forest/truth/frame_truth.hpp"
#include "bench_paths.hpp"
#include "run_output.hpp"

namespace forest::app {
namespace {

using Clock = std::chrono::steady_clock;
using nlohmann::ordered_json;

struct ImpostorsOptions {
  GlOptions gl;
  std::string scene;
  std::vector<std::string> paths;
  int trees = 200000;
  int repeats = 5;        // timed frames per representation, alternating
  int dollyFrames = 40;
  double dollyStep = 2.0;  // metres a frame, backward along the view
  ImageSizeOptions size;
  std::string out = "out/bench-impostors";
  FrameOptions frame;
  bool quiet = false;
};

// A view rendered after two frames at it (what a frame hands the next), and its image.
struct Rendered {
  render::FrameStats stats;
  Image8 image;
};
Rendered renderSettled(render::Frame& frame, const Camera& camera, double time, const render::FrameSettings& settings) {
  for (int k = 0; k < 2; ++k) frame.render(camera, time, settings);
  Rendered r{frame.render(camera, time, settings), {}};
  r.image = frame.readColor();
  return r;
}

// The pixels (top row first) whose surface lies at least `distance` from the eye — not the sky.
std::vector<std::uint8_t> pixelsBeyond(const render::Frame& frame, const Camera& camera, double distance) {
  const std::vector<float> depth = frame.readDepth();  // bottom row first, reversed-Z
  const int w = frame.width(), h = frame.height();
  std::vector<std::uint8_t> mask(depth.size(), 0);
  const double tanHalf = std::tan(camera.fovy / 2.0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float d = depth[static_cast<size_t>(y) * w + x];
      if (d <= 0.0f) continue;
      // Distance along the pixel's ray: eye depth × |(ndc x · tan · aspect, ndc y · tan, 1)|.
      const double nx = (2.0 * (x + 0.5) / w - 1.0) * tanHalf * camera.aspect, ny = (2.0 * (y + 0.5) / h - 1.0) * tanHalf;
      const double along = camera.eyeDepthOfReversedZ(d) * std::sqrt(1.0 + nx * nx + ny * ny);
      mask[static_cast<size_t>(h - 1 - y) * w + x] = along >= distance ? 1 : 0;
    }
  return mask;
}

ordered_json differenceJson(const Image8& a, const Image8& b, const std::vector<std::uint8_t>& mask) {
  const PixelDifference d = pixelDifference(a, b, mask);
  return {{"ssim", meanSsim(a, b, mask)}, {"mean_abs_255", d.meanAbsolute}, {"share_over_8", d.shareOver8}};
}

double misclassifiedBeyond200m(const render::Frame& frame, const render::FrameStats& stats, const Scene& scene, const Camera& camera,
                               double time) {
  truth::TruthOptions options;
  options.softRays = 0;
  options.bandEdges = {200.0};
  return truth::evaluateFrame(frame, stats, scene, camera, time, options).bands.back().misclassification;
}

// The median frame time of each representation, `repeats` frames each, taking turns.
std::pair<double, double> alternatingFrameMs(render::Frame& frame, const Camera& camera, double time, render::FrameSettings settings,
                                             double distance, int repeats) {
  std::vector<double> ms[2];
  for (int k = 0; k < 2 * repeats; ++k) {
    settings.impostorDistance = k % 2 ? distance : 0.0;
    const auto start = Clock::now();
    frame.render(camera, time, settings);
    glFinish();
    ms[k % 2].push_back(std::chrono::duration<double, std::milli>(Clock::now() - start).count());
  }
  return {percentile(ms[0], 0.5), percentile(ms[1], 0.5)};
}

// The mean |Δ| (1/255) between consecutive frames of a dolly back from `camera`, `frames` frames of
// `step` metres, with `settings` as given.
double dollyChange(render::Frame& frame, const Camera& camera, double time, const render::FrameSettings& settings, int frames, double step) {
  frame.resetHistory();
  Image8 previous;
  double sum = 0.0;
  for (int f = 0; f < frames; ++f) {
    Camera c = camera;
    c.position -= static_cast<double>(f) * step * c.forward();
    frame.render(c, time, settings);
    Image8 image = frame.readColor();
    if (f > 0) sum += pixelDifference(previous, image).meanAbsolute;
    previous = std::move(image);
  }
  return frames > 1 ? sum / (frames - 1) : 0.0;
}

ordered_json measureView(const ImpostorsOptions& options, const Scene& scene, const Camera& view, double time, const std::string& name,
                         const gl::Context& context) {
  const std::filesystem::path out = options.out;
  render::FrameSettings settings = options.frame.settings(context.info());
  const double asked = settings.impostorDistance;  // metres, or auto
  render::Frame frame(scene, options.size.width, options.size.height);
  const Rendered impostors = renderSettled(frame, view, time, settings);
  const double distance = impostors.stats.impostorDistance;  // resolved
  const double impostorError = misclassifiedBeyond200m(frame, impostors.stats, scene, view, time);
  settings.impostorDistance = 0.0;
  const Rendered meshes = renderSettled(frame, view, time, settings);
  const std::vector<std::uint8_t> beyond = pixelsBeyond(frame, view, distance);
  const double meshError = misclassifiedBeyond200m(frame, meshes.stats, scene, view, time);
  const auto [meshMs, impostorMs] = alternatingFrameMs(frame, view, time, settings, asked, options.repeats);
  settings.impostorDistance = 0.0;
  const double dollyOff = dollyChange(frame, view, time, settings, options.dollyFrames, options.dollyStep);
  settings.impostorDistance = asked;
  const double dollyOn = dollyChange(frame, view, time, settings, options.dollyFrames, options.dollyStep);
  Scene allLod0 = scene;
  allLod0.vegetation->force_lod0 = true;
  settings.impostorDistance = 0.0;
  render::Frame lod0Frame(allLod0, options.size.width, options.size.height);
  const Rendered lod0 = renderSettled(lod0Frame, view, time, settings);
  writeImage(out / (name + "-meshes.png"), meshes.image);
  writeImage(out / (name + "-impostors.png"), impostors.image);
  writeImage(out / (name + "-lod0.png"), lod0.image);
  long long beyondPixels = 0;
  for (std::uint8_t b : beyond) beyondPixels += b;
  return {{"view", name},
          {"impostor_distance_m", distance},
          {"pixels_beyond_switch", beyondPixels},
          {"impostors_vs_meshes", differenceJson(impostors.image, meshes.image, beyond)},
          {"lod_chain_vs_lod0", differenceJson(meshes.image, lod0.image, beyond)},
          {"misclassification_beyond_200m", {{"meshes", meshError}, {"impostors", impostorError}}},
          {"eye_triangles", {{"meshes", meshes.stats.geometryTriangles}, {"impostors", impostors.stats.geometryTriangles}}},
          {"shadow_triangles", {{"meshes", meshes.stats.shadowTriangles}, {"impostors", impostors.stats.shadowTriangles}}},
          {"frame_ms_p50", {{"meshes", meshMs}, {"impostors", impostorMs}}},
          {"dolly_mean_change_255", {{"switch_off", dollyOff}, {"switch_on", dollyOn}}}};
}

std::string tableOf(const ordered_json& views) {
  std::string md = fmt::format(
      "| view | switch distance, pixels beyond it | SSIM impostors / meshes | SSIM LOD chain / LOD0 | mean abs diff (1/255), impostors / LOD chain | "
      "misclassified beyond 200 m, meshes → impostors | eye triangles | shadow triangles | frame p50 ms | dolly change on / off |\n"
      "|---|---|---|---|---|---|---|---|---|---|\n");
  for (const ordered_json& v : views) {
    const auto& m = v["misclassification_beyond_200m"];
    const double meshes = m["meshes"].get<double>(), impostors = m["impostors"].get<double>();
    const auto pair = [&](const char* key, double scale, const char* unit) {
      return fmt::format("{:.0f}{} → {:.0f}{}", v[key]["meshes"].get<double>() / scale, unit, v[key]["impostors"].get<double>() / scale, unit);
    };
    const double off = v["dolly_mean_change_255"]["switch_off"].get<double>(), on = v["dolly_mean_change_255"]["switch_on"].get<double>();
    md += fmt::format("| {} | {:.0f} m, {} | {:.4f} | {:.4f} | {:.2f} / {:.2f} | {:.2f}% → {:.2f}% ({:.2f}×) | {} | {} | {} | {:.3f} / {:.3f} ({:.2f}×) |\n",
                      v["view"].get<std::string>(), v["impostor_distance_m"].get<double>(), v["pixels_beyond_switch"].get<long long>(), v["impostors_vs_meshes"]["ssim"].get<double>(),
                      v["lod_chain_vs_lod0"]["ssim"].get<double>(), v["impostors_vs_meshes"]["mean_abs_255"].get<double>(),
                      v["lod_chain_vs_lod0"]["mean_abs_255"].get<double>(), 100.0 * meshes, 100.0 * impostors,
                      meshes > 0.0 ? impostors / meshes : 0.0, pair("eye_triangles", 1e3, " k"), pair("shadow_triangles", 1e3, " k"),
                      pair("frame_ms_p50", 1.0, " ms"), on, off, off > 0.0 ? on / off : 0.0);
  }
  return md;
}

int runBenchImpostors(const ImpostorsOptions& options) {
  const std::string scenePath = options.scene.empty() ? (resourceDirectory("data") / "scenes" / "landscape.toml").string() : options.scene;
  const Scene full = loadScene(scenePath);
  if (!full.terrain || !full.vegetation || full.vegetation->grid > 0)
    throw InputError(scenePath + ": bench impostors needs a scene with [terrain] and [vegetation] placed by count (not a grid)");
  if (options.trees > full.vegetation->count)
    throw InputError(fmt::format("--trees {}: at most the scene's count, {}", options.trees, full.vegetation->count));
  if (options.frame.impostors != "on")
    throw InputError("bench impostors compares impostors with meshes: leave --impostors at on (the default here)");
  std::vector<std::string> pathFiles = options.paths;
  if (pathFiles.empty())
    for (const char* name : {"landscape-walk.toml", "landscape-flight.toml"}) pathFiles.push_back((resourceDirectory("data") / "paths" / name).string());
  const std::filesystem::path out = options.out;
  std::filesystem::create_directories(out);
  auto context = options.gl.open(options.size.width, options.size.height);
  const std::string device = gl::describe(context->info());
  ordered_json json = {{"device", device}, {"scene", scenePath}, {"trees", options.trees},
                       {"resolution", {options.size.width, options.size.height}},
                       {"settings", options.frame.json(context->info(), full)}, {"views", ordered_json::array()}};
  for (const std::string& file : pathFiles) {
    const CameraPath path = CameraPath::load(file);
    const std::string name = std::filesystem::path(file).stem().string();
    const Scene scene = sceneWithTrees(full, path, options.trees);
    if (!options.quiet) std::cerr << fmt::format("bench impostors: {} trees, the last view of {} ...\n", options.trees, name);
    const terrain::Terrain terrain(*scene.terrain);
    const double fps = 1.0;
    const int frames = path.frameCount(fps);
    const Camera last = filePath(path, scene, terrain, frames, fps, static_cast<double>(options.size.width) / options.size.height).back();
    json["views"].push_back(measureView(options, scene, last, path.startTime() + (frames - 1) / fps, name, *context));
  }
  if (gl::debugErrorCount() > 0) throw Error(fmt::format("{} GL errors (first: {})", gl::debugErrorCount(), gl::debugErrorMessages().front()));
  const std::string md =
      "# Far trees as impostors against their meshes\n\n" + benchmarkStamp(device) +
      fmt::format("\n\n`forest bench impostors` on {} with {} trees at its stand density around each path, {}x{}, impostors from "
                  "--impostor-distance {} (cross-faded over the next 10%). Differences over the pixels beyond the switch distance (not the sky); SSIM: Wang et al. "
                  "2004 on luma (1: alike). Misclassification: the ray-traced truth, which traces every tree's mesh. Frame times: median "
                  "of {} frames each, taking turns. Dolly: {} frames {:.0f} m a frame backward from the view, mean |Δ| between frames.\n\n",
                  shownPath(scenePath), options.trees, options.size.width, options.size.height, options.frame.impostorDistance,
                  options.repeats, options.dollyFrames, options.dollyStep) +
      tableOf(json["views"]);
  writeFileAtomic(out / "impostors.json", json.dump(1) + "\n");
  writeFileAtomic(out / "impostors.md", md);
  std::cout << md << fmt::format("\nwrote {0}/impostors.json, {0}/impostors.md and the views' images\n", shownPath(out));
  return 0;
}

}  // namespace

Run addImpostorsBenchCommand(CLI::App& bench) {
  auto options = std::make_shared<ImpostorsOptions>();
  options->frame.impostors = "on";
  CLI::App* command = bench.add_subcommand(
      "impostors",
      "Far trees as impostors against their meshes: at each landscape path's last view, the impostor frame's\n"
      "difference to the all-mesh frame beyond the switch distance next to the LOD chain's to all-LOD0 (SSIM,\n"
      "mean |diff|), misclassification beyond 200 m with impostor and mesh casters (ray-traced truth), triangles,\n"
      "frame times, and the change between frames of a dolly across the switch. Writes impostors.json,\n"
      "impostors.md and the views' images");
  options->gl.add(*command);
  command->add_option("--scene", options->scene, "Scene file (default: data/scenes/landscape.toml)")->check(CLI::ExistingFile);
  command->add_option("--paths", options->paths, "Camera paths, comma-separated (default: data/paths/landscape-walk.toml and -flight.toml)")
      ->delimiter(',')
      ->check(CLI::ExistingFile);
  command->add_option("--trees", options->trees, "Trees at the scene's stand density around each path (1 to 10^6, at most the scene's count)")
      ->check(CLI::Range(1, 1000000))
      ->capture_default_str();
  command->add_option("--repeats", options->repeats, "Timed frames per representation (1 to 100)")->check(CLI::Range(1, 100))->capture_default_str();
  command->add_option("--dolly-frames", options->dollyFrames, "Frames of the dolly (2 to 1000)")->check(CLI::Range(2, 1000))->capture_default_str();
  command->add_option("--dolly-step", options->dollyStep, "Metres a dolly frame moves back (0.01 to 100)")->check(CLI::Range(0.01, 100.0))->capture_default_str();
  options->size.add(*command);
  command->add_option("--out", options->out, "Output folder (created when missing)")->check(outputFolder())->capture_default_str();
  command->add_flag("--quiet", options->quiet, "No progress line");
  options->frame.add(*command);
  return [options] { return runBenchImpostors(*options); };
}

}  // namespace forest::app
