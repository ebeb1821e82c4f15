// forest walkthrough: the main job. Renders a camera path through a scene with the full frame
// (culling, LiSPSM shadows, lighting), headless, and writes every 10th frame, an MP4 of every frame
// (ffmpeg), a contact sheet, report.json (one record per frame) and a one-screen summary. Ctrl-C stops
// after the current frame and still writes complete files for the frames done.
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <iostream>
#include <optional>

#include "commands.hpp"
#include "run_output.hpp"
#include "forest/core/heap.hpp"
#include "forest/core/camera_path.hpp"
#include "forest/core/error.hpp"
#include "forest/core/files.hpp"
#include "forest/core/image.hpp"
#include "forest/core/log.hpp"
#include "forest/core/resources.hpp"
#include "forest/core/scene.hpp"
#include "forest/gl/context.hpp"
#include "forest/gl/debug.hpp"
#include "forest/gl/objects.hpp"
#include "forest/render/frame.hpp"

namespace forest::app {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

std::atomic<bool> gInterrupted{false};
extern "C" void onInterrupt(int) { gInterrupted = true; }


}  // namespace

nlohmann::ordered_json frameRecord(int index, double time, bool warmup, const Camera& camera, double yawDeg, double frameMs,
                                   const render::FrameStats& s) {
  nlohmann::ordered_json r;
  r["frame"] = index;
  r["time"] = time;
  r["warmup"] = warmup;
  r["eye"] = {camera.position.x, camera.position.y, camera.position.z};
  r["yaw_deg"] = yawDeg;
  r["frame_ms"] = frameMs;
  for (FramePass pass : kFramePassNames.values()) r["passes_ms"][std::string(kFramePassNames.name(pass))] = s.passMs[pass];
  r["visible_objects"] = s.visibleObjects;
  r["hidden_by_reprojection"] = s.hiddenByReprojection;
  r["casters"] = s.casterObjects;
  r["caster_receivers"] = s.casterReceivers;
  r["triangles"] = {{"geometry", s.geometryTriangles}, {"shadow", s.shadowTriangles}};
  r["queries"] = s.culling.queriesIssued;
  r["culling_cpu_ms"] = s.culling.cpuMilliseconds;
  r["draw_calls"] = s.culling.drawCalls;
  r["culled_by_frustum"] = s.culledByFrustum;
  r["z_f"] = s.farDepth;
  r["far"] = camera.far;
  r["n"] = s.shadow.n;
  r["gamma_deg"] = s.shadow.gammaDeg;
  r["sun_below_horizon"] = s.sunBelowHorizon;
  r["impostor_distance_m"] = s.impostorDistance;
  r["cascades"] = cascadesJson(s);
  r["gpu_memory_mib"] = static_cast<double>(gl::gpuMemory().bytes) / (1 << 20);
  r["rss_mib"] = residentMegabytes();
  return r;
}

nlohmann::ordered_json cascadesJson(const render::FrameStats& s) {
  nlohmann::ordered_json slices = nlohmann::ordered_json::array();
  for (int i = 0; i < s.cascades; ++i) {
    const render::CascadeStats& c = s.cascade[static_cast<size_t>(i)];
    slices.push_back({{"from_m", c.fromM}, {"to_m", c.toM}, {"map_size", c.mapSize}, {"n", c.n}, {"gamma_deg", c.gammaDeg},
                      {"casters", c.casters}, {"triangles", c.triangles}, {"texels_drawn", c.texelsDrawn},
                      {"shadow_ms", c.shadowMs}, {"kept", c.keeping.kept}, {"kept_frames", c.keeping.keptFrames},
                      {"refit", c.keeping.refit}, {"update", render::kSliceUpdateNames.name(c.update)}, {"redraw", c.redraw}, {"deferred", c.deferred}});
  }
  return slices;
}

void recordPassTimes(const std::vector<gl::FrameTiming>& timings, nlohmann::ordered_json& records) {
  for (const gl::FrameTiming& t : timings) {
    if (t.frame >= records.size()) continue;
    nlohmann::ordered_json& passes = records[t.frame]["passes_ms"];
    for (const gl::PassTime& pass : t.passes) passes[pass.pass] = pass.ms;
  }
}

nlohmann::ordered_json summariseFrames(const nlohmann::ordered_json& records, int measured) {
  nlohmann::ordered_json summary;
  auto column = [&](const std::function<double(const nlohmann::ordered_json&)>& get) {
    std::vector<double> v;
    for (const auto& r : records)
      if (!r["warmup"].template get<bool>()) v.push_back(get(r));
    double sum = 0.0;
    for (double x : v) sum += x;
    return nlohmann::ordered_json{{"mean", v.empty() ? 0.0 : sum / static_cast<double>(v.size())},
                                  {"p50", percentile(v, 0.5)},
                                  {"p95", percentile(v, 0.95)},
                                  {"p99", percentile(v, 0.99)}};
  };
  summary["frame_ms"] = column([](const auto& r) { return r["frame_ms"].template get<double>(); });
  if (!records.empty() && records.front().contains("interval_ms"))
    summary["interval_ms"] = column([](const auto& r) { return r["interval_ms"].template get<double>(); });
  for (const std::string& pass : kFramePassNames.names())
    summary["passes_ms"][pass] = column([&pass](const auto& r) { return r["passes_ms"][pass].template get<double>(); });
  summary["triangles_geometry"] = column([](const auto& r) { return r["triangles"]["geometry"].template get<double>(); });
  summary["triangles_shadow"] = column([](const auto& r) { return r["triangles"]["shadow"].template get<double>(); });
  summary["casters"] = column([](const auto& r) { return r["casters"].template get<double>(); });
  summary["queries"] = column([](const auto& r) { return r["queries"].template get<double>(); });
  summary["culling_cpu_ms"] = column([](const auto& r) { return r["culling_cpu_ms"].template get<double>(); });
  summary["draw_calls"] = column([](const auto& r) { return r["draw_calls"].template get<double>(); });
  summary["frames_measured"] = measured;
  int byFrustum = 0;
  for (const auto& r : records)
    if (!r["warmup"].template get<bool>() && r.value("culled_by_frustum", false)) ++byFrustum;
  summary["frames_culled_by_frustum"] = byFrustum;
  return summary;
}

nlohmann::ordered_json startupRecord(const render::Frame& frame) {
  nlohmann::ordered_json r;
  double total = 0.0;
  for (const render::StartupStep& step : frame.startupSteps()) {
    r[std::string(step.name) + "_ms"] = step.ms;
    total += step.ms;
  }
  r["total_ms"] = total;
  const std::vector<render::StartupStep>& steps = frame.startupSteps();
  r["rss_mib"] = steps.empty() ? 0.0 : steps.back().rssMib;
  r["heap_mib"] = steps.empty() ? 0.0 : steps.back().heapMib;
  const size_t trees = frame.forest() ? frame.forest()->trees().size() : 0;
  // The heap in use added after the terrain, per tree: what the trees cost in every later step
  // (a heap count, not RSS, so that runs in one process each count their own).
  const auto terrain = std::find_if(steps.begin(), steps.end(), [](const render::StartupStep& s) { return std::string_view(s.name) == "terrain"; });
  r["bytes_per_tree"] = trees > 0 && terrain != steps.end() ? (steps.back().heapMib - terrain->heapMib) * (1 << 20) / static_cast<double>(trees) : 0.0;
  return r;
}

std::string startupLine(const nlohmann::ordered_json& startup) {
  std::string steps;
  for (const auto& [key, value] : startup.items())
    if (key.ends_with("_ms") && key != "total_ms")
      steps += fmt::format("{}{} {:.1f}", steps.empty() ? "" : ", ", key.substr(0, key.size() - 3), value.get<double>() / 1e3);
  return fmt::format("start-up {:.1f} s ({} s), {:.0f} MiB resident, {:.0f} bytes per tree", startup["total_ms"].get<double>() / 1e3, steps,
                     startup["rss_mib"].get<double>(), startup["bytes_per_tree"].get<double>());
}

void printSummary(const nlohmann::ordered_json& summary) {
  const auto& frameMs = summary["frame_ms"];
  std::cout << fmt::format("  {:<13} {:>9} {:>9} {:>9} {:>9}\n", "ms", "mean", "p50", "p95", "p99");
  std::cout << fmt::format("  {:<13} {:>9.2f} {:>9.2f} {:>9.2f} {:>9.2f}\n", "frame", frameMs["mean"].get<double>(),
                           frameMs["p50"].get<double>(), frameMs["p95"].get<double>(), frameMs["p99"].get<double>());
  if (summary.contains("interval_ms")) {
    const auto& interval = summary["interval_ms"];
    std::cout << fmt::format("  {:<13} {:>9.2f} {:>9.2f} {:>9.2f} {:>9.2f}\n", "interval", interval["mean"].get<double>(),
                             interval["p50"].get<double>(), interval["p95"].get<double>(), interval["p99"].get<double>());
  }
  for (const std::string& pass : kFramePassNames.names()) {
    const auto& p = summary["passes_ms"][pass];
    std::cout << fmt::format("  {:<13} {:>9.2f} {:>9.2f} {:>9.2f} {:>9.2f}\n", pass, p["mean"].get<double>(), p["p50"].get<double>(),
                             p["p95"].get<double>(), p["p99"].get<double>());
  }
  std::cout << fmt::format("  mean per frame: {:.0f} eye triangles, {:.0f} shadow triangles, {:.0f} casters, {:.0f} queries, "
                           "culler {:.2f} ms CPU\n",
                           summary["triangles_geometry"]["mean"].get<double>(), summary["triangles_shadow"]["mean"].get<double>(),
                           summary["casters"]["mean"].get<double>(), summary["queries"]["mean"].get<double>(),
                           summary["culling_cpu_ms"]["mean"].get<double>());
  std::cout << fmt::format("  {} of {} frames drawn by frustum culling, where chc++'s queries did not pay ([culling] query_payoff)\n",
                           summary["frames_culled_by_frustum"].get<int>(), summary["frames_measured"].get<int>());
}

// A frame of the run, as its outputs name it.
struct WalkFrame {
  int index;
  bool last;
  double time, frameMs;
};

// The run's own outputs of a frame — its PNG, its contact-sheet thumbnail, its video frame — and
// the between-frames hook: the CPU seconds they took, which the frame's interval leaves out.
double writeFrameOutputs(const WalkthroughOptions& options, render::Frame& frame, const WalkFrame& f, const fs::path& out,
                         ContactSheet& sheet, std::optional<VideoWriter>& video) {
  const bool writeFrame = f.index % options.every == 0 || f.last;
  const bool videoFrame = video && video->ok();
  double outputSeconds = 0.0;
  if (writeFrame || sheet.wants(f.index) || videoFrame) {
    // Waits for the frame: that wait stays in the interval, except for a frame read for the video only.
    const auto readStart = Clock::now();
    const Image8 image = frame.readColor();
    const auto outputStart = writeFrame || sheet.wants(f.index) ? Clock::now() : readStart;
    if (writeFrame) writeImage(out / "frames" / fmt::format("frame{:05d}.png", f.index), image);
    if (sheet.wants(f.index)) sheet.add(f.index, f.time, f.frameMs, image);
    if (videoFrame) video->add(image);
    outputSeconds = std::chrono::duration<double>(Clock::now() - outputStart).count();
  }
  if (options.betweenFrames && f.index % kBetweenFramesEvery == kBetweenFramesEvery - 1) {
    glFinish();  // the frame's work stays in its interval, the hook's does not
    const auto hookStart = Clock::now();
    options.betweenFrames();
    outputSeconds += std::chrono::duration<double>(Clock::now() - hookStart).count();
  }
  return outputSeconds;
}

// What a walkthrough renders, each part checked before any output exists.
struct WalkInput {
  std::string scenePath, pathPath;
  Scene scene;
  CameraPath path;
  render::FrameSettings settings;
  int total, warmup;
};

WalkInput checkedWalkInput(const WalkthroughOptions& options) {
  const std::string scenePath = sceneFileOr(options.scene);
  const std::string pathPath = walkPathOr(options.path);
  Scene scene = loadScene(scenePath);
  CameraPath path = CameraPath::load(pathPath);
  if (path.aboveGround() && !scene.terrain) throw InputError(pathPath + ": heights = \"above_ground\" needs a scene with [terrain]");
  render::FrameSettings settings = options.frame.settings();  // names checked before anything opens
  settings.keepShadowTerm = false;  // the run shows and times frames; nothing reads the term back
  settings.wholeShadowMap = false;  // nothing reads the map back
  const int pathFrames = path.frameCount(options.fps);
  const int total = options.length.frames > 0 ? std::min(options.length.frames, pathFrames) : pathFrames;
  const int warmup = options.length.warmupFor(total);
  if (warmup >= total)
    throw InputError(fmt::format("--warmup {}: expected fewer than the {} frames the run renders", warmup, total));
  return {scenePath, pathPath, std::move(scene), std::move(path), settings, total, warmup};
}

int runWalkthrough(const WalkthroughOptions& options) {
  WalkInput input = checkedWalkInput(options);
  auto& [scenePath, pathPath, scene, path, settings, total, warmup] = input;
  const int width = options.size.width, height = options.size.height;
  scene.render.width = width;
  scene.render.height = height;

  auto context = options.gl.open(width, height);
  const std::string device = gl::describe(context->info());
  options.frame.resolveModes(settings, context->info());
  render::Frame frame(scene, width, height);

  // The folder holds this run only: what an earlier walkthrough wrote there goes first.
  const fs::path out(options.out);
  clearEarlierWalk(out);
  fs::create_directories(out / "frames");
  std::signal(SIGINT, onInterrupt);
  std::optional<VideoWriter> video;
  if (options.video) video.emplace(out / "walkthrough.mp4", width, height, options.fps);
  nlohmann::ordered_json records = nlohmann::ordered_json::array();
  ContactSheet sheet;
  const auto start = Clock::now();
  int done = 0;
  // A frame's interval: from its start to the next frame's (after the last, to the end of its GPU
  // work), less the CPU's time on this run's own outputs (shrinking and writing images). It holds
  // the frame's GPU work whatever the timing mode, without a wait inside any frame (DESIGN §9):
  // the time between frames a viewer sees.
  Clock::time_point previousStart;
  double previousOutputSeconds = 0.0;
  auto closeInterval = [&](Clock::time_point next) {
    if (records.empty()) return;
    records.back()["interval_ms"] = 1e3 * (std::chrono::duration<double>(next - previousStart).count() - previousOutputSeconds);
  };
  for (int f = 0; f < total && !gInterrupted; ++f) {
    const double time = path.startTime() + f / options.fps;
    const CameraPose pose = path.at(time);
    const Camera camera = frame.cameraAt(pose, path.aboveGround());
    const auto frameStart = Clock::now();
    closeInterval(frameStart);
    const render::FrameStats s = frame.render(camera, time, settings);
    const double frameMs = 1e3 * std::chrono::duration<double>(Clock::now() - frameStart).count();
    const double outputSeconds = writeFrameOutputs(options, frame, {f, f == total - 1, time, frameMs}, out, sheet, video);
    records.push_back(frameRecord(f, time, f < warmup, camera, pose.yaw_deg, frameMs, s));
    recordPassTimes(frame.takePassTimes(), records);  // timer queries: earlier frames' pass times
    ++done;
    showProgress("walkthrough", "frames", done, total, std::chrono::duration<double>(Clock::now() - start).count(), options.length.quiet);
    previousStart = frameStart;
    previousOutputSeconds = outputSeconds;
  }
  glFinish();  // the last frame's GPU work, for its interval
  closeInterval(Clock::now());
  std::signal(SIGINT, SIG_DFL);
  recordPassTimes(frame.drainPassTimes(), records);
  // The last frame done is always on the sheet (its image is still in the frame's target).
  if (done > 0 && !sheet.has(done - 1)) {
    const nlohmann::ordered_json& last = records.back();
    sheet.add(done - 1, last["time"].get<double>(), last["frame_ms"].get<double>(), frame.readColor());
  }
  if (gl::debugErrorCount() > 0)
    throw Error(fmt::format("{} GL errors during the walkthrough (first: {})", gl::debugErrorCount(), gl::debugErrorMessages().front()));

  const nlohmann::ordered_json summary = summariseFrames(records, done - std::min(done, warmup));
  nlohmann::ordered_json report = {{"scene", scenePath},
                                   {"path", pathPath},
                                   {"device", device},
                                   {"resolution", {width, height}},
                                   {"settings", options.frame.json(context->info(), scene)},
                                   {"warmup_frames", warmup},
                                   {"frames_requested", total},
                                   {"frames_done", done},
                                   {"interrupted", gInterrupted.load()},
                                   {"startup", startupRecord(frame)},
                                   {"summary", summary},
                                   {"frames", std::move(records)}};
  report["settings"]["fps"] = options.fps;
  writeFileAtomic(out / "report.json", report.dump(1) + "\n");
  if (!sheet.empty()) writeImage(out / "contact-sheet.png", sheet.compose());

  // The video's last frames are encoded now (VideoWriter).
  const bool videoDone = video && video->finish();
  const std::string noVideo = !video ? "" : fmt::format(" (no MP4: {})", video->why());

  // Paths as every command shows them (shownPath; the report keeps them absolute).
  const int slices = render::resolveCascades(options.frame.settings(), scene).cascades;
  std::cout << fmt::format("walkthrough: {} of {} frames of {} along {} at {}x{} ({}, {}, {})\n", done, total,
                           shownPath(scenePath), shownPath(pathPath), width, height, options.frame.method,
                           render::shadowLayoutLabel(options.frame.settings(), slices), options.frame.culling);
  if (warmup > 0) std::cout << fmt::format("  (the first {} frames are warm-up, not in the summary)\n", warmup);
  std::cout << "  " << startupLine(report["startup"]) << "\n";
  printSummary(summary);
  const std::string shownOut = shownPath(out);
  const std::string frames = options.every == kFirstFrameOnly ? std::string("the first frame") : fmt::format("frames every {}", options.every);
  std::cout << fmt::format("  wrote {}/report.json, {}/contact-sheet.png, {} in {}/frames{}\n", shownOut, shownOut,
                           frames, shownOut, videoDone ? fmt::format(", walkthrough.mp4 of all {} frames", done) : noVideo);
  if (gInterrupted) {
    std::cout << "  interrupted: the report holds the frames done\n";
    return 130;
  }
  return 0;
}

void WalkthroughOptions::add(CLI::App& command, bool withFramesOut) {
  gl.add(command);
  command.add_option("--scene", scene, "Scene file (default: data/scenes/forest.toml, 5000 trees)");
  command.add_option("--path", path, "Camera path (default: data/paths/walk.toml; --window starts at its start)");
  command.add_option("--out", out, "Output folder, created when missing (what an earlier run of this command wrote there is\nremoved first)")
      ->check(outputFolder())
      ->capture_default_str();
  if (withFramesOut) {
    size.add(command);
    command.add_option("--fps", fps, "Frames per second of path time (0.1 to 1000)")->check(CLI::Range(0.1, 1000.0))->capture_default_str();
    command.add_option("--every", every, "Write every k-th frame as PNG (1 to 1000000; 1: all)")->check(CLI::Range(1, 1000000))->capture_default_str();
    video = true;
    command.add_flag("--video,!--no-video", video,
                     "walkthrough.mp4 of every frame (the default; needs ffmpeg). Each frame is then read back: on a GPU\n"
                     "that waits for it (its interval excludes the read-back and the encoding); time a GPU with --no-video");
  } else {
    size.add(command, " (default: the budget file's)");
  }
  length.add(command, withFramesOut ? "the whole path" : "the budget file's");
  frame.add(command);
}

Run addWalkthroughCommand(CLI::App& app) {
  auto options = std::make_shared<WalkthroughOptions>();
  CLI::App* command = app.add_subcommand(
      "walkthrough",
      "The main job: render a camera path through a scene (culling, LiSPSM shadows, lighting), headless;\n"
      "write every 10th frame, walkthrough.mp4 of every frame, a contact sheet, report.json (fields:\n"
      "docs/report-format.md) and a summary");
  options->add(*command, true);
  auto window = std::make_shared<WindowOptions>();
  auto windowed = std::make_shared<bool>(false);
  CLI::Option* windowFlag = command->add_flag(
      "--window", *windowed,
      "Interactive: a GLFW window (needs a display), mouse look and WASD; keys switch culling, shadow method,\n"
      "map size, blur, move the sun and freeze culling (H shows them). Writes report.json and window.png\n"
      "into --out; --frames stops after that many frames");
  command->add_option("--script", window->script, "Drive the window with a timed input script (TOML; see docs/scene-format.md)")
      ->needs(windowFlag);
  command->add_option("--record", window->record, "Write the camera path flown in the window (replay it with --path)")
      ->needs(windowFlag);
  return [options, window, windowed] { return *windowed ? runWindow(*options, *window) : runWalkthrough(*options); };
}

}  // namespace forest::app
