// forest bench speed-error: shadow methods × focus bounds × map sizes × scenarios, each frame timed
// and measured against the ray-traced truth (truth/), with flicker along a short moving path.
// Writes report.json (docs/speed-error.md), results.csv, table.md, plots with the Pareto front per
// scenario, and the error image of each method's worst case.
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>

#include "commands.hpp"
#include "forest/core/error.hpp"
#include "forest/core/files.hpp"
#include "forest/core/log.hpp"
#include "forest/core/plot.hpp"
#include "forest/core/scene.hpp"
#include "forest/gl/context.hpp"
#include "forest/gl/debug.hpp"
#include "forest/terrain/terrain.hpp"
#include "forest/truth/frame_truth.hpp"
#include "forest/vegetation/forest.hpp"

namespace forest::app {
namespace {

using Clock = std::chrono::steady_clock;
using glm::dvec3;
using nlohmann::ordered_json;

struct SpeedErrorOptions {
  GlOptions gl;
  std::string scene;
  std::string out = "out/speed-error";
  bool quick = false;
  ImageSizeOptions size{1280, 720};
  std::vector<int> sizes{512, 1024, 2048, 4096};
  double target = 0.02;  // misclassification for the equal-error map sizes
  int softRays = 8;      // fewer than truth's 16: the sweep scores 130 frames
  ModeOptions modes;
  bool quiet = false;
};

const std::vector<std::string> kMethods{"uniform", "uniform-stable", "lispsm", "tsm"};
const std::vector<std::string> kFocus{"receivers", "frustum"};

struct Scenario {
  std::string name;
  Camera camera;
  dvec3 sun;  // the way light travels
};

// The light's direction for a sun `elevationDeg` above the horizon whose light travels at
// `azimuthDeg` from the camera's horizontal forward (0: along the view, the sun behind the eye).
dvec3 sunRelativeTo(const Camera& camera, double elevationDeg, double azimuthDeg) {
  dvec3 forward = camera.forward();
  forward.y = 0.0;
  forward = glm::normalize(forward);
  const dvec3 right = glm::normalize(glm::cross(forward, dvec3(0, 1, 0)));
  const double e = glm::radians(elevationDeg), a = glm::radians(azimuthDeg);
  return glm::normalize(std::cos(e) * (std::cos(a) * forward + std::sin(a) * right) - std::sin(e) * dvec3(0, 1, 0));
}

// Ground level (the scene's start) and above the canopy (30 m higher, 20° down), suns at 15°, 45°,
// 75° from behind-left; dueling frusta: looking down along the light (sun behind, 30°) and up into it
// (sun ahead, 20°); with stands, under the canopy of the densest stand (5° up) and in a clearing
// beside it, looking at it, sun at 45°.
std::vector<Scenario> makeScenarios(const Scene& scene, const render::Frame& frame, bool quick) {
  const Camera ground = frame.startCamera();
  Camera canopy = ground;
  canopy.position.y += 30.0;
  canopy.pitch = glm::radians(-20.0);
  std::vector<Scenario> all;
  for (double elevation : {15.0, 45.0, 75.0}) all.push_back({fmt::format("ground, sun {:.0f} deg", elevation), ground, sunRelativeTo(ground, elevation, 135.0)});
  for (double elevation : {15.0, 45.0, 75.0}) all.push_back({fmt::format("canopy, sun {:.0f} deg", elevation), canopy, sunRelativeTo(canopy, elevation, 135.0)});
  Camera behind = ground;
  behind.pitch = glm::radians(-30.0);
  all.push_back({"dueling, sun behind", behind, sunRelativeTo(behind, 30.0, 0.0)});
  Camera ahead = ground;
  ahead.pitch = glm::radians(20.0);
  all.push_back({"dueling, sun ahead", ahead, sunRelativeTo(ahead, 20.0, 180.0)});
  // Under the canopy of the densest stand and in a clearing beside it, looking at it (with stands).
  if (const vegetation::Forest* forest = frame.forest(); forest && forest->stands() && frame.terrain()) {
    const terrain::Terrain& terrain = *frame.terrain();
    const glm::dvec2 stand = vegetation::densestStand(*forest), clearing = clearingNear(*forest, terrain.bounds(), stand);
    const double above = scene.camera.above_ground.value_or(1.7);
    Camera under = ground;
    under.position = dvec3(stand.x, terrain.heightAt(stand.x, stand.y) + above, stand.y);
    under.pitch = glm::radians(5.0);
    all.push_back({"under the canopy, sun 45 deg", under, sunRelativeTo(under, 45.0, 135.0)});
    Camera open = ground;
    open.position = dvec3(clearing.x, terrain.heightAt(clearing.x, clearing.y) + above, clearing.y);
    const glm::dvec2 toStand = stand - clearing;
    if (glm::length(toStand) > 1.0) open.yaw = std::atan2(-toStand.x, -toStand.y);
    open.pitch = 0.0;
    all.push_back({"clearing, sun 45 deg", open, sunRelativeTo(open, 45.0, 135.0)});
  }
  if (quick) return {all[1], all[6]};
  return all;
}

struct Row {
  std::string scenario, method, focus;
  int mapSize = 0;
  bool blur = false;
  double frameMs = 0.0, shadowMs = 0.0;
  truth::FrameError error;
  double softError = 0.0;  // of the term lighting used (blurred or not)
};

render::FrameSettings settingsFor(const std::string& method, const std::string& focus, int mapSize) {
  render::FrameSettings settings;
  settings.method = shadows::parseShadowMethod(method);
  settings.focus = render::parseFocusBound(focus);
  settings.shadowMapSize = mapSize;
  return settings;
}

const glm::vec3 kMethodColour[] = {{0.85f, 0.2f, 0.15f}, {0.95f, 0.6f, 0.1f}, {0.15f, 0.45f, 0.85f}, {0.2f, 0.65f, 0.3f}};

glm::vec3 methodColour(const std::string& method) {
  const auto it = std::find(kMethods.begin(), kMethods.end(), method);
  return kMethodColour[it - kMethods.begin()];
}

// One image: a panel per scenario, frame (or shadow-pass) ms against an error figure, a series per
// method, the Pareto front in black.
void writePlot(const std::filesystem::path& file, const std::vector<Scenario>& scenarios, const std::vector<Row>& rows,
               const std::string& xLabel, double (*x)(const Row&), bool shadowPass) {
  std::vector<PlotPanel> panels;
  for (const Scenario& s : scenarios) {
    PlotPanel panel;
    panel.title = s.name;
    panel.xLabel = xLabel;
    panel.yLabel = shadowPass ? "shadow pass ms" : "frame ms";
    std::vector<glm::dvec2> all;
    for (const std::string& method : kMethods) {
      PlotSeries series{method, methodColour(method), {}, false};
      for (const Row& r : rows)
        if (r.scenario == s.name && r.method == method) series.points.emplace_back(x(r), shadowPass ? r.shadowMs : r.frameMs);
      all.insert(all.end(), series.points.begin(), series.points.end());
      panel.series.push_back(std::move(series));
    }
    panel.series.push_back({"Pareto front", glm::vec3(0.0f), paretoFront(all), true});
    panels.push_back(std::move(panel));
  }
  writeImage(file, plotPanels(panels, std::min<int>(4, static_cast<int>(panels.size()))));
}

int runSpeedError(const SpeedErrorOptions& options) {
  const std::string scenePath = sceneFileOr(options.scene);
  Scene scene = loadScene(scenePath);
  for (int size : options.sizes)
    if (size < 512 || size > 8192) throw InputError(fmt::format("--sizes {}: expected 512 to 8192 texels", size));
  if (!(options.target > 0.0 && options.target < 1.0)) throw InputError("--target: expected a share in (0, 1)");
  const std::filesystem::path out = options.out;
  std::filesystem::create_directories(out);
  const std::vector<int> sizes = options.quick ? std::vector<int>{1024} : options.sizes;
  const int width = options.quick ? 640 : options.size.width, height = options.quick ? 360 : options.size.height;

  gl::ContextOptions contextOptions;
  contextOptions.backend = gl::parseBackend(options.gl.backend);
  contextOptions.width = width;
  contextOptions.height = height;
  auto context = gl::createContext(contextOptions);
  log::info("{}", gl::describe(context->info()));
  render::Frame frame(scene, width, height);
  const std::vector<Scenario> scenarios = makeScenarios(scene, frame, options.quick);

  truth::TruthOptions truthOptions;
  truthOptions.softRays = options.softRays;
  const int flickerRuns = static_cast<int>(kMethods.size() * kFocus.size() * sizes.size());
  const int total = static_cast<int>(scenarios.size() * kMethods.size() * kFocus.size() * sizes.size()) + flickerRuns;
  int done = 0;
  const auto start = Clock::now();
  auto tick = [&] {
    ++done;
    showProgress("speed-error", "runs", done, total, std::chrono::duration<double>(Clock::now() - start).count(), options.quiet);
  };

  std::vector<Row> rows;
  std::map<std::string, std::pair<double, Image8>> worst;  // per method: misclassification, error image
  for (const Scenario& s : scenarios) {
    scene.sun.direction = s.sun;
    Camera camera = s.camera;
    camera.aspect = static_cast<double>(width) / height;
    for (const std::string& method : kMethods)
      for (const std::string& focus : kFocus)
        for (int size : sizes) {
          render::FrameSettings settings = settingsFor(method, focus, size);
          options.modes.resolve(settings, context->info());
          settings.blurRadius = 3.0;
          // One frame to settle CHC and the smoothed n, then the measured one.
          frame.resetHistory();
          frame.render(camera, 0.0, settings);
          const render::FrameStats stats = renderWithPassTimes(frame, camera, 0.0, settings);
          Row r;
          r.scenario = s.name;
          r.method = method;
          r.focus = focus;
          r.mapSize = size;
          r.error = truth::evaluateFrame(frame, stats, scene, camera, 0.0, truthOptions);
          r.shadowMs = stats.shadowMs;
          const double frameMs = stats.passesMs();
          // Blur on (as rendered) and off: the same frame rendered again with no blur at all (no
          // horizontal pass, no vertical half in the lighting), timed on its own; the history it
          // starts from is the measured frame's, as that one's was the settling frame's.
          // Misclassification is of the unblurred term in both.
          render::FrameSettings noBlur = settings;
          noBlur.blurRadius = 0.0;
          const render::FrameStats offStats = renderWithPassTimes(frame, camera, 0.0, noBlur);
          Row on = r, off = r;
          on.blur = true;
          on.frameMs = frameMs;
          on.softError = r.error.softMeanAbsoluteError;
          off.blur = false;
          off.frameMs = offStats.passesMs();
          off.shadowMs = offStats.shadowMs;
          off.softError = r.error.softMeanAbsoluteErrorUnblurred;
          if (worst[method].second.empty() || r.error.misclassification > worst[method].first)
            worst[method] = {r.error.misclassification, r.error.errorImage};
          on.error.errorImage = Image8();
          off.error.errorImage = Image8();
          rows.push_back(std::move(on));
          rows.push_back(std::move(off));
          tick();
        }
  }

  // Flicker: the first scenario's sun, the camera walking 0.4 m and turning 0.3° per frame.
  scene.sun.direction = scenarios.front().sun;
  std::vector<Camera> path;
  for (int i = 0; i < 8; ++i) {
    Camera c = scenarios.front().camera;
    c.aspect = static_cast<double>(width) / height;
    c.yaw += glm::radians(0.3 * i);
    c.position += 0.4 * i * c.forward();
    path.push_back(c);
  }
  ordered_json flicker = ordered_json::array();
  std::map<std::string, std::vector<glm::dvec2>> flickerPoints;  // method → (share, frame ms)
  for (const std::string& method : kMethods)
    for (const std::string& focus : kFocus)
      for (int size : sizes) {
        render::FrameSettings settings = settingsFor(method, focus, size);
        options.modes.resolve(settings, context->info());
        frame.resetHistory();
        const truth::FlickerResult f = truth::measureFlicker(frame, scene, path, 0.0, settings);
        flicker.push_back({{"method", method}, {"focus", focus}, {"map_size", size}, {"share", f.share()},
                           {"probes", f.probes}, {"comparisons", f.comparisons}, {"changes", f.changes}});
        double frameMs = 0.0;
        for (const Row& r : rows)
          if (r.scenario == scenarios.front().name && r.method == method && r.focus == focus && r.mapSize == size && r.blur)
            frameMs = r.frameMs;
        flickerPoints[method].emplace_back(f.share(), frameMs);
        tick();
      }
  if (gl::debugErrorCount() > 0)
    throw Error(fmt::format("{} GL errors during the sweep (first: {})", gl::debugErrorCount(), gl::debugErrorMessages().front()));

  // Equal-error map sizes: per scenario and method (B from the receivers), the smallest size whose
  // misclassification is at most the target.
  ordered_json equalError;
  for (const Scenario& s : scenarios)
    for (const std::string& method : kMethods) {
      ordered_json size = nullptr;
      for (int candidate : sizes) {
        const auto it = std::find_if(rows.begin(), rows.end(), [&](const Row& r) {
          return r.scenario == s.name && r.method == method && r.focus == "receivers" && r.mapSize == candidate && r.blur;
        });
        if (it != rows.end() && it->error.misclassification <= options.target) {
          size = candidate;
          break;
        }
      }
      equalError[s.name][method] = size;
    }

  // report.json, results.csv, table.md.
  ordered_json report;
  report["version"] = 1;
  report["scene"] = scenePath;
  report["device"] = gl::describe(context->info());
  report.update(options.modes.json(context->info()));
  report["resolution"] = {width, height};
  report["quick"] = options.quick;
  report["map_sizes"] = sizes;
  report["soft_rays"] = options.softRays;
  report["target_misclassification"] = options.target;
  report["scenarios"] = ordered_json::array();
  for (const Scenario& s : scenarios)
    report["scenarios"].push_back({{"name", s.name},
                                   {"camera", {s.camera.position.x, s.camera.position.y, s.camera.position.z}},
                                   {"yaw_deg", glm::degrees(s.camera.yaw)},
                                   {"pitch_deg", glm::degrees(s.camera.pitch)},
                                   {"sun_direction", {s.sun.x, s.sun.y, s.sun.z}}});
  std::ostringstream csv;
  csv << "scenario,method,focus,map_size,blur,frame_ms,shadow_ms,misclassification,near_edge,elsewhere,false_shadow,"
         "false_light,soft_mae,aliasing_p95_px,aliasing_max_px,casters_selected,casters_needed,casters_missing\n";
  report["rows"] = ordered_json::array();
  for (const Row& r : rows) {
    const truth::FrameError& e = r.error;
    report["rows"].push_back({{"scenario", r.scenario},
                              {"method", r.method},
                              {"focus", r.focus},
                              {"map_size", r.mapSize},
                              {"blur", r.blur},
                              {"frame_ms", r.frameMs},
                              {"shadow_ms", r.shadowMs},
                              {"misclassification", e.misclassification},
                              {"near_edge", e.misclassificationNearEdge},
                              {"elsewhere", e.misclassificationElsewhere},
                              {"false_shadow", e.falseShadow},
                              {"false_light", e.falseLight},
                              {"soft_mae", options.softRays > 0 ? nlohmann::ordered_json(r.softError) : nlohmann::ordered_json()},
                              {"aliasing_p95_px", e.aliasingPixels.p95},
                              {"aliasing_max_px", e.aliasingPixels.max},
                              {"lit_facing_pixels", e.litFacing},
                              {"casters_selected", e.casters.selected},
                              {"casters_needed", e.casters.needed},
                              {"casters_missing", e.casters.missing}});
    csv << fmt::format("\"{}\",{},{},{},{},{:.3f},{:.3f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.4f},{:.4f},{},{},{}\n", r.scenario,
                       r.method, r.focus, r.mapSize, r.blur ? 1 : 0, r.frameMs, r.shadowMs, e.misclassification,
                       e.misclassificationNearEdge, e.misclassificationElsewhere, e.falseShadow, e.falseLight, r.softError,
                       e.aliasingPixels.p95, e.aliasingPixels.max, e.casters.selected, e.casters.needed, e.casters.missing);
  }
  report["flicker"] = flicker;
  report["equal_error_map_size"] = equalError;

  std::ostringstream md;
  md << fmt::format("Speed against error: {} at {}x{}, B from the visible receivers, blur 3 px ({}).\n\n"
                    "Misclassified lit-facing pixels (%) / frame ms, per map size:\n\n",
                    std::filesystem::path(scenePath).filename().string(), width, height, gl::describe(context->info()));
  md << "| scenario | method |";
  for (int size : sizes) md << fmt::format(" {}² |", size);
  md << " equal-error size (≤ " << 100 * options.target << "%) |\n|---|---|";
  for (size_t i = 0; i <= sizes.size(); ++i) md << "---|";
  md << "\n";
  for (const Scenario& s : scenarios)
    for (const std::string& method : kMethods) {
      md << "| " << s.name << " | " << method << " |";
      for (int size : sizes)
        for (const Row& r : rows)
          if (r.scenario == s.name && r.method == method && r.focus == "receivers" && r.mapSize == size && r.blur)
            md << fmt::format(" {:.2f} / {:.0f} |", 100 * r.error.misclassification, r.frameMs);
      const ordered_json& e = equalError[s.name][method];
      md << " " << (e.is_null() ? std::string("> ") + std::to_string(sizes.back()) : std::to_string(e.get<int>())) << " |\n";
    }
  md << "\nFlicker (share of probe states that change between consecutive frames, " << scenarios.front().name
     << ", walking 0.4 m and turning 0.3 deg per frame), B from the receivers:\n\n| method |";
  for (int size : sizes) md << fmt::format(" {}² |", size);
  md << "\n|---|";
  for (size_t i = 0; i < sizes.size(); ++i) md << "---|";
  md << "\n";
  for (const std::string& method : kMethods) {
    md << "| " << method << " |";
    for (int size : sizes)
      for (const auto& f : flicker)
        if (f["method"] == method && f["focus"] == "receivers" && f["map_size"] == size) md << fmt::format(" {:.4f} |", f["share"].get<double>());
    md << "\n";
  }

  writeFileAtomic(out / "report.json", report.dump(2) + "\n");
  writeFileAtomic(out / "results.csv", csv.str());
  writeFileAtomic(out / "table.md", md.str());
  writePlot(out / "frame-ms-vs-misclassification.png", scenarios, rows, "misclassified pixels (share)",
            [](const Row& r) { return r.error.misclassification; }, false);
  writePlot(out / "shadow-ms-vs-misclassification.png", scenarios, rows, "misclassified pixels (share)",
            [](const Row& r) { return r.error.misclassification; }, true);
  if (options.softRays > 0)  // --soft-rays 0: no soft truth, no plot of it
    writePlot(out / "frame-ms-vs-soft-error.png", scenarios, rows, "mean |term - soft truth|", [](const Row& r) { return r.softError; },
              false);
  writePlot(out / "frame-ms-vs-aliasing.png", scenarios, rows, "aliasing p95 (px per texel)",
            [](const Row& r) { return r.error.aliasingPixels.p95; }, false);
  {
    PlotPanel panel;
    panel.title = "flicker, " + scenarios.front().name + " (moving camera)";
    panel.xLabel = "share of probes changing state per frame";
    panel.yLabel = "frame ms";
    std::vector<glm::dvec2> all;
    for (const std::string& method : kMethods) {
      panel.series.push_back({method, methodColour(method), flickerPoints[method], false});
      all.insert(all.end(), flickerPoints[method].begin(), flickerPoints[method].end());
    }
    panel.series.push_back({"Pareto front", glm::vec3(0.0f), paretoFront(all), true});
    writeImage(out / "frame-ms-vs-flicker.png", plotPanels({panel}, 1));
  }
  for (const auto& [method, w] : worst) writeImage(out / fmt::format("worst-{}.png", method), w.second);

  std::cout << md.str() << fmt::format("\nwrote {}/report.json, results.csv, table.md, 5 plots, {} worst-case error images\n",
                                       out.string(), worst.size());
  return 0;
}

}  // namespace

Run addSpeedErrorCommand(CLI::App& bench) {
  auto options = std::make_shared<SpeedErrorOptions>();
  CLI::App* command = bench.add_subcommand(
      "speed-error",
      "Speed against error: shadow methods (uniform, uniform-stable, lispsm, tsm) x focus body bound (visible\n"
      "receivers, frustum) x map sizes x scenarios (ground-level and above-canopy cameras, suns at 15, 45, 75\n"
      "degrees, dueling frusta), each frame timed and measured against the ray-traced truth; flicker along a\n"
      "short walk. Writes report.json (docs/speed-error.md), results.csv, table.md, plots with the Pareto front,\n"
      "the error image of each method's worst case.");
  options->gl.add(*command);
  command->add_option("--scene", options->scene, "Scene file (default: data/scenes/forest.toml)");
  command->add_option("--out", options->out, "Output folder")->capture_default_str();
  command->add_flag("--quick", options->quick, "All methods at 1024² on two scenarios at 640x360 (CI; under 3 minutes)");
  options->size.add(*command);
  command->add_option("--sizes", options->sizes, "Shadow map sizes, texels per side (comma-separated, 512 to 8192)")
      ->delimiter(',')
      ->check(CLI::Range(512, 8192))
      ->capture_default_str();
  command->add_option("--target", options->target, "Misclassification share for the equal-error map sizes (0 to 1, exclusive)")
      ->check(CLI::Range(1e-6, 0.999999))
      ->capture_default_str();
  addSoftRaysOption(*command, options->softRays);
  options->modes.add(*command);
  command->add_flag("--quiet", options->quiet, "No progress bar");
  return [options] { return runSpeedError(*options); };
}

}  // namespace forest::app
