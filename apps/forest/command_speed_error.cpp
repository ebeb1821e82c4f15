// forest bench speed-error: shadow methods × focus bounds × map layouts (one map, or K slices at
// equal total texels) × scenarios, each frame timed and measured against the ray-traced truth
// (truth/), with flicker along a short moving path. The report (speed_error_report.cpp):
// report.json (docs/speed-error.md), results.csv, table.md, plots with the Pareto front per
// scenario, and the error image of each method's worst case.
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <functional>
#include <iostream>
#include <map>
#include <memory>

#include "forest/core/error.hpp"
#include "forest/core/image.hpp"
#include "forest/core/log.hpp"
#include "forest/gl/context.hpp"
#include "forest/gl/debug.hpp"
#include "forest/shadows/kept_slices.hpp"
#include "forest/terrain/terrain.hpp"
#include "forest/vegetation/forest.hpp"
#include "speed_error.hpp"

namespace forest::app {

int MapLayout::farSize() const { return cascades == 1 ? layerSize : static_cast<int>(std::lround(farScale * layerSize)); }

long long MapLayout::texels() const {
  return static_cast<long long>(cascades - 1) * layerSize * layerSize + static_cast<long long>(farSize()) * farSize();
}

std::string MapLayout::label() const {
  render::FrameSettings settings;
  settings.shadowMapSize = layerSize;
  settings.farSliceScale = static_cast<double>(farSize()) / layerSize;
  return render::shadowLayoutLabel(settings, cascades);
}

std::string seriesName(const std::string& method, int cascades) {
  return cascades == 1 ? method : fmt::format("{} x{}", method, cascades);  // ASCII: the plots' font has no ×
}

std::vector<MapLayout> mapLayouts(const std::vector<int>& sizes, const std::vector<int>& cascades, double farScale) {
  std::vector<MapLayout> layouts;
  for (int k : cascades)
    for (int size : sizes) {
      // (K − 1) · layer² + (r · layer)² = size².
      const double r = k == 1 ? 1.0 : farScale;
      const int layer = static_cast<int>(std::lround(size / std::sqrt(k - 1 + r * r)));
      if (layer >= 512) layouts.push_back({k, layer, size, r});
    }
  return layouts;
}

namespace {

using Clock = std::chrono::steady_clock;
using glm::dvec3;
using nlohmann::ordered_json;

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

render::FrameSettings settingsFor(const std::string& method, const std::string& focus, const MapLayout& layout) {
  render::FrameSettings settings;
  settings.method = shadows::kShadowMethodNames.parse(method);
  settings.focus = render::kFocusBoundNames.parse(focus);
  settings.shadowMapSize = layout.layerSize;
  settings.cascades = layout.cascades;
  settings.farSliceScale = static_cast<double>(layout.farSize()) / layout.layerSize;  // the rounded side exactly
  return settings;
}

// Cascades are swept with B on the visible receivers only (their slices are bounded by the visible set).
std::vector<std::string> focusBoundsFor(const MapLayout& layout) {
  return layout.cascades == 1 ? kSpeedErrorFocus : std::vector<std::string>{"receivers"};
}

// One setting at one view: a frame to settle CHC, the smoothed n and the splits, then the measured
// one (the blur as asked) and the same frame again with no blur at all (no horizontal pass, no
// vertical half in the lighting), timed on its own and starting from the measured frame's history,
// as that one did from the settling frame's. Each is scored on the term it lit with: blurred, and
// the blur off's looked up. Returns (blur on, blur off), their labels left to the caller.
std::pair<Row, Row> measureRun(render::Frame& frame, const Scene& scene, const Camera& camera, const render::FrameSettings& settings,
                               const truth::TruthOptions& truthOptions) {
  frame.resetHistory();
  frame.render(camera, 0.0, settings);
  const render::FrameStats stats = renderWithPassTimes(frame, camera, 0.0, settings);
  Row on;
  on.error = truth::evaluateFrame(frame, stats, scene, camera, 0.0, truthOptions);
  on.blur = true;
  on.frameMs = stats.passMs.total();
  on.shadowMs = stats.passMs[FramePass::Shadow];
  on.shadowTriangles = stats.shadowTriangles;
  on.softError = on.error.softMeanAbsoluteError;
  render::FrameSettings noBlur = settings;
  noBlur.blurRadius = 0.0;
  const render::FrameStats offStats = renderWithPassTimes(frame, camera, 0.0, noBlur);
  Row off = on;
  off.error = truth::evaluateFrame(frame, offStats, scene, camera, 0.0, truthOptions);
  off.blur = false;
  off.frameMs = offStats.passMs.total();
  off.shadowMs = offStats.passMs[FramePass::Shadow];
  off.softError = off.error.softMeanAbsoluteError;  // (the blur off: the term it lit with is unblurred)
  return {std::move(on), std::move(off)};
}

constexpr int kFlickerFrames = 16;

// The walk at 30 frames a second with `settings` (kept slices), redrawn every frame, cached and
// staggered.
CachedWalk measureCachedWalk(render::Frame& frame, const Scene& scene, std::span<const Camera> path, render::FrameSettings settings,
                             truth::TruthOptions options) {
  CachedWalk walk;
  walk.measured = true;
  options.softRays = 0;
  const double lastTime = static_cast<double>(path.size() - 1) / 30.0;
  for (WalkPass* pass : {&walk.redrawn, &walk.cached, &walk.staggered}) {
    settings.cacheSlices = pass != &walk.redrawn;
    settings.staggerSlices = pass == &walk.staggered;
    frame.resetHistory();
    render::FrameStats stats;
    for (size_t i = 0; i < path.size(); ++i) {
      stats = frame.render(path[i], static_cast<double>(i) / 30.0, settings);
      pass->triangles += stats.shadowTriangles;
      for (int slice = 0; slice < stats.cascades; ++slice) {
        const render::SliceUpdate update = stats.cascade[static_cast<size_t>(slice)].update;
        ++(update == render::SliceUpdate::Reuse ? pass->reused : update == render::SliceUpdate::Add ? pass->added : pass->redrawn);
      }
    }
    pass->lastView = truth::evaluateFrame(frame, stats, scene, path.back(), lastTime, options);
    pass->lastView.errorImage = Image8();
  }
  return walk;
}

// Flicker along a short walk from the first scenario's camera (its sun already set): 16 frames,
// walking 0.4 m and turning 0.3° per frame, per layout, method and focus, and again with kept
// slices for the methods that do not hold still by themselves; then the walk's last view once more,
// scored against the truth; with kept slices, the swaying walk redrawn, cached and staggered
// (CachedWalk).
std::vector<FlickerRow> measureFlickerWalks(render::Frame& frame, const Scene& scene, const Scenario& first,
                                            const std::vector<MapLayout>& layouts, const std::vector<Row>& rows,
                                            const std::function<render::FrameSettings(const MapLayout&, const std::string&, const std::string&)>& settingsOf,
                                            const truth::TruthOptions& truthOptions, const std::function<void()>& tick) {
  std::vector<Camera> path;
  for (int i = 0; i < kFlickerFrames; ++i) {
    Camera c = first.camera;
    c.aspect = static_cast<double>(frame.width()) / frame.height();
    c.yaw += glm::radians(0.3 * i);
    c.position += 0.4 * i * c.forward();
    path.push_back(c);
  }
  std::vector<FlickerRow> flicker;
  for (const MapLayout& layout : layouts)
    for (const std::string& method : kSpeedErrorMethods)
      for (const std::string& focus : focusBoundsFor(layout))
        for (bool keep : {false, true}) {
          if (keep && shadows::holdsStillByItself(shadows::kShadowMethodNames.parse(method))) continue;
          render::FrameSettings settings = settingsOf(layout, method, focus);
          settings.keepSlices = keep;
          frame.resetHistory();
          FlickerRow f{method, focus, layout, keep, truth::measureFlicker(frame, scene, path, 0.0, settings), 0.0, {}, 0, {}};
          for (const Row& r : rows)
            if (r.scenario == first.name && r.method == method && r.focus == focus && r.layout.label() == layout.label() && r.blur)
              f.frameMs = r.frameMs;
          const render::FrameStats stats = frame.render(path.back(), 0.0, settings);
          truth::TruthOptions options = truthOptions;
          options.softRays = 0;
          f.lastView = truth::evaluateFrame(frame, stats, scene, path.back(), 0.0, options);
          f.lastView.errorImage = Image8();
          f.lastViewShadowTriangles = stats.shadowTriangles;
          if (keep) f.cached = measureCachedWalk(frame, scene, path, settings, truthOptions);
          flicker.push_back(std::move(f));
          tick();
        }
  return flicker;
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
  const std::vector<MapLayout> layouts = mapLayouts(sizes, options.cascades, options.farSliceScale);
  const int width = options.quick ? 640 : options.size.width, height = options.quick ? 360 : options.size.height;

  auto context = options.gl.open(width, height);
  const render::CasterSelection casters = options.casters.resolve(context->info());
  render::Frame frame(scene, width, height);
  const std::vector<Scenario> scenarios = makeScenarios(scene, frame, options.quick);

  truth::TruthOptions truthOptions;
  truthOptions.softRays = options.softRays;
  int runsPerScenario = 0;
  for (const MapLayout& layout : layouts) runsPerScenario += static_cast<int>(kSpeedErrorMethods.size() * focusBoundsFor(layout).size());
  int flickerRuns = 0;  // with and without kept slices
  for (const MapLayout& layout : layouts)
    for (const std::string& method : kSpeedErrorMethods)
      flickerRuns += static_cast<int>(focusBoundsFor(layout).size()) * (shadows::holdsStillByItself(shadows::kShadowMethodNames.parse(method)) ? 1 : 2);
  const int total = runsPerScenario * static_cast<int>(scenarios.size()) + flickerRuns;
  int done = 0;
  const auto start = Clock::now();
  auto tick = [&] {
    ++done;
    showProgress("speed-error", "runs", done, total, std::chrono::duration<double>(Clock::now() - start).count(), options.quiet);
  };

  std::vector<Row> rows;
  std::map<std::string, std::pair<double, Image8>> worst;  // per method (-xK): misclassification, error image
  for (const Scenario& s : scenarios) {
    scene.sun.direction = s.sun;
    Camera camera = s.camera;
    camera.aspect = static_cast<double>(width) / height;
    for (const MapLayout& layout : layouts)
      for (const std::string& method : kSpeedErrorMethods)
        for (const std::string& focus : focusBoundsFor(layout)) {
          render::FrameSettings settings = settingsFor(method, focus, layout);
          options.modes.resolve(settings, context->info());
          settings.casters = casters;
          settings.blurRadius = 3.0;
          settings.shadowTermScale = options.termResolution == "half" ? 2 : 1;
          auto [on, off] = measureRun(frame, scene, camera, settings, truthOptions);
          on.scenario = off.scenario = s.name;
          on.method = off.method = method;
          on.focus = off.focus = focus;
          on.layout = off.layout = layout;
          const std::string series = layout.cascades == 1 ? method : fmt::format("{}-x{}", method, layout.cascades);
          if (worst[series].second.empty() || on.error.misclassification > worst[series].first)
            worst[series] = {on.error.misclassification, on.error.errorImage};
          on.error.errorImage = Image8();
          off.error.errorImage = Image8();
          rows.push_back(std::move(on));
          rows.push_back(std::move(off));
          tick();
        }
  }

  scene.sun.direction = scenarios.front().sun;
  const std::vector<FlickerRow> flicker = measureFlickerWalks(frame, scene, scenarios.front(), layouts, rows, [&](const MapLayout& layout,
      const std::string& method, const std::string& focus) {
    render::FrameSettings settings = settingsFor(method, focus, layout);
    options.modes.resolve(settings, context->info());
    settings.casters = casters;
    return settings;
  }, truthOptions, tick);
  if (gl::debugErrorCount() > 0)
    throw Error(fmt::format("{} GL errors during the sweep (first: {})", gl::debugErrorCount(), gl::debugErrorMessages().front()));

  nlohmann::ordered_json modes = options.modes.json(context->info());
  modes["casters"] = render::kCasterSelectionNames.name(casters);
  const std::string table = writeSpeedErrorReport(out, options, scenePath, gl::describe(context->info()), modes,
                                                  width, height, scenarios, layouts, rows, flicker);
  for (const auto& [series, w] : worst) writeImage(out / fmt::format("worst-{}.png", series), w.second);
  std::cout << table << fmt::format("\nwrote {}/report.json, results.csv, table.md, 5 plots, {} worst-case error images\n", shownPath(out),
                                    worst.size());
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
  command->add_option("--out", options->out, "Output folder (created when missing)")->check(outputFolder())->capture_default_str();
  command->add_flag("--quick", options->quick, "All methods at 1024² on two scenarios at 640x360 (CI; under 3 minutes)");
  options->size.add(*command);
  command->add_option("--sizes", options->sizes, "Shadow map sizes, texels per side (comma-separated, 512 to 8192)")
      ->delimiter(',')
      ->check(CLI::Range(512, 8192))
      ->capture_default_str();
  command->add_option("--cascades", options->cascades,
                      "Slices per layout (comma-separated, 1 to 4): K > 1 at equal total texels, K layers of\n"
                      "(size / sqrt K)² per size (4 x 1024² beside 2048²), B on the receivers")
      ->delimiter(',')
      ->check(CLI::Range(1, shadows::kMaxCascades))
      ->capture_default_str();
  command->add_option("--far-slice-scale", options->farSliceScale,
                      "Unequal layers: with K > 1 the last layer's side is this many times the others' at the\n"
                      "same total texels, (K - 1 + scale²) · layer² = size² (0.5 to 2; 1: equal layers)")
      ->check(CLI::Range(0.5, 2.0))
      ->capture_default_str();
  command->add_option("--target", options->target, "Misclassification share for the equal-error map sizes (1e-06 to 0.999999)")
      ->check(CLI::Range(1e-6, 0.999999))
      ->capture_default_str();
  command->add_option("--term-resolution", options->termResolution, "Resolution of the blurred shadow term (as the frame's flag)")
      ->check(CLI::IsMember({"full", "half"}))
      ->capture_default_str();
  addSoftRaysOption(*command, options->softRays);
  options->modes.add(*command);
  options->casters.add(*command);
  command->add_flag("--quiet", options->quiet, "No progress bar");
  return [options] { return runSpeedError(*options); };
}

}  // namespace forest::app
