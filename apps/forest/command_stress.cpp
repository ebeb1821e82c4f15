// forest stress: polygon-rich dynamic scenes. For each tree count (terrain grown to keep the default
// density) and LOD0 budget: a walk with a share of the trees and 20 props moved every frame (BVH
// refit), a day cycle of the sun and wind; per frame times, triangles, queries, RSS and heap in use; on sampled
// frames the culled (chc++) geometry pass (depth and object IDs) is compared with frustum culling's. Writes
// stress.json and stress.png (scaling curves); exit 1 when culling was not exact.
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <functional>
#include <iostream>
#include <memory>
#include <numbers>
#include <numeric>

#include "commands.hpp"
#include "run_output.hpp"
#include "forest/core/heap.hpp"
#include "forest/core/error.hpp"
#include "forest/core/files.hpp"
#include "forest/core/log.hpp"
#include "forest/core/plot.hpp"
#include "forest/core/random.hpp"
#include "forest/core/scene.hpp"
#include "forest/gl/context.hpp"
#include "forest/gl/debug.hpp"

namespace forest::app {

Scene scaledScene(const Scene& base, int trees, int lod0) {
  Scene scene = base;
  if (!scene.terrain || !scene.vegetation) throw InputError(base.source + ": scaling the tree count needs [terrain] and [vegetation]");
  TerrainSettings& t = *scene.terrain;
  const double spacing = t.size / (t.samples - 1);
  t.size *= std::sqrt(static_cast<double>(trees) / std::max(1, base.vegetation->count));
  t.size = std::clamp(t.size, 64.0, 65536.0);
  const int quads = std::clamp(static_cast<int>(std::lround(t.size / spacing / 64.0)) * 64, 64, 8192);
  t.samples = quads + 1;
  t.feature_size *= t.size / base.terrain->size;
  scene.vegetation->count = trees;
  scene.vegetation->lod0_triangles = lod0;
  return scene;
}

namespace {

using Clock = std::chrono::steady_clock;
using glm::dvec3;
using nlohmann::ordered_json;

struct StressOptions {
  GlOptions gl;
  std::string scene;
  std::string out = "out/stress";
  std::vector<int> trees{1000, 5000, 20000, 100000};
  std::vector<int> lod0{2000};
  ImageSizeOptions size{640, 360};
  RunLengthOptions length{300, 50};  // frames per run; warm-up before the RSS slope and the statistics
  FrameOptions frame;
  double moving = 0.02;  // share of the trees moved every frame
  int checkEvery = 50;   // frames between exactness checks (0: none)
};

constexpr int kProps = 20;
// A memory slope is given in % per 100 frames: from fewer measured frames it would extrapolate
// beyond the run, and one allocation early in the run would read as a trend. Shorter runs leave
// the slopes out (null) and say so.
constexpr int kMinSlopeFrames = 100;
// Exactness sampled on fewer frames than this is reported with a warning (one checked frame is
// one view, not a walk).
constexpr int kMinCheckedFrames = 3;


// Least-squares slope of y over x.
double slope(const std::vector<double>& y) {
  const double n = static_cast<double>(y.size());
  if (n < 2) return 0.0;
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (size_t i = 0; i < y.size(); ++i) {
    const double x = static_cast<double>(i);
    sx += x;
    sy += y[i];
    sxx += x * x;
    sxy += x * y[i];
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

// A memory series (MiB per measured frame): first, last, least-squares slope in % of its mean per
// 100 frames (null from fewer than kMinSlopeFrames frames), every 10th value.
ordered_json memoryTrend(const std::vector<double>& mib) {
  const double mean = mib.empty() ? 0.0 : std::accumulate(mib.begin(), mib.end(), 0.0) / static_cast<double>(mib.size());
  std::vector<double> every10th;
  for (size_t k = 0; k < mib.size(); k += 10) every10th.push_back(mib[k]);
  ordered_json slopePercent = nullptr;
  if (static_cast<int>(mib.size()) >= kMinSlopeFrames) slopePercent = mean > 0.0 ? 100.0 * 100.0 * slope(mib) / mean : 0.0;
  return {{"first", mib.empty() ? 0.0 : mib.front()}, {"last", mib.empty() ? 0.0 : mib.back()},
          {"slope_percent_per_100_frames", slopePercent}, {"every_10th_frame", every10th}};
}

// The sun over the run: rising at 5°, 85° at the middle, setting again, turning a full circle.
dvec3 daySun(double phase) {
  const double elevation = glm::radians(5.0 + 80.0 * std::sin(std::numbers::pi * phase));
  const double azimuth = 2.0 * std::numbers::pi * phase;
  return {std::cos(elevation) * std::cos(azimuth), -std::sin(elevation), std::cos(elevation) * std::sin(azimuth)};
}

struct RunResult {
  ordered_json json;
  double frameP50 = 0.0;
  long long mismatched = 0;
};

// Exactness: the pixels (object ID or depth) where the frame just rendered differs from frustum
// culling's geometry pass on the same moved scene — its own culler and no shadow setup, so the next
// timed frame keeps its CHC history and n.
long long pixelsUnlikeFrustumCulling(render::Frame& frame, const Camera& camera, double time) {
  const std::vector<std::uint32_t> ids = frame.readObjectIds();
  const std::vector<float> depth = frame.readDepth();
  frame.renderReferenceGeometry(camera, time);
  const std::vector<std::uint32_t> idsF = frame.readObjectIds();
  const std::vector<float> depthF = frame.readDepth();
  long long mismatched = 0;
  for (size_t p = 0; p < ids.size(); ++p) mismatched += ids[p] != idsF[p] || depth[p] != depthF[p] ? 1 : 0;
  return mismatched;
}

RunResult runOne(const Scene& base, int trees, int lod0, const StressOptions& options, const gl::ContextInfo& context, int& done, int total,
                 Clock::time_point start) {
  Scene scene = scaledScene(base, trees, lod0);
  // Props: 2 m boxes, built first as placeholders (the frame needs their count), then put around the
  // walk's start on the ground once the terrain exists.
  scene.props.assign(kProps, PropBox{dvec3(0.0), dvec3(2.0), dvec3(0.7, 0.3, 0.2)});
  render::Frame frame(scene, options.size.width, options.size.height);
  const std::vector<Camera> path =
      walkPath(scene, *frame.terrain(), options.length.frames, static_cast<double>(options.size.width) / options.size.height);
  std::vector<dvec3> centres;
  for (int i = 0; i < kProps; ++i) {
    const double a = 2.0 * std::numbers::pi * i / kProps;
    centres.push_back(path.front().position + dvec3(12.0 * std::cos(a), 0.0, 12.0 * std::sin(a)));
  }
  render::FrameSettings settings = options.frame.settings(context);
  settings.keepShadowTerm = false;  // timed; nothing reads the term back
  settings.wholeShadowMap = false;  // nothing reads the map back
  SplitMix64 random(SplitMix64::substream(scene.vegetation->seed, 0x57e55ull));
  const int treeCount = static_cast<int>(frame.forest()->trees().size());
  const int movedPerFrame = static_cast<int>(std::lround(options.moving * treeCount));
  std::vector<double> frameMs, rss, heap;
  std::vector<double> geometryByFrame(static_cast<size_t>(options.length.frames), 0.0);  // timer queries fill it late
  auto takeGeometryTimes = [&](const std::vector<gl::FrameTiming>& timings) {
    for (const gl::FrameTiming& t : timings) {
      render::FrameStats timed;
      timed.setPassTimes(t);
      geometryByFrame[t.frame] = timed.passMs[FramePass::Geometry];
    }
  };
  std::vector<long long> trianglesGeometry, trianglesShadow, queries;
  long long mismatched = 0;
  int checks = 0;
  for (int i = 0; i < options.length.frames; ++i) {
    // Moves: a share of the trees up to 0.5 m, every prop along its circle.
    std::vector<vegetation::Forest::Move> moves;
    for (int k = 0; k < movedPerFrame; ++k) {
      const auto t = static_cast<std::uint32_t>(random.unit() * treeCount) % static_cast<std::uint32_t>(treeCount);
      const dvec3 p = frame.forest()->trees()[t].position;
      moves.push_back({t, glm::dvec2(p.x + random.uniform(-0.5, 0.5), p.z + random.uniform(-0.5, 0.5)), frame.forest()->trees()[t].yaw});
    }
    frame.moveTrees(moves);
    std::vector<PropMove> propMoves;
    for (int k = 0; k < kProps; ++k) {
      const double a = 0.05 * i + k;
      const dvec3 c = centres[static_cast<size_t>(k)] + dvec3(3.0 * std::cos(a), 0.0, 3.0 * std::sin(a));
      propMoves.push_back({static_cast<std::uint32_t>(k), dvec3(c.x - 1, frame.terrain()->heightAt(c.x, c.z), c.z - 1)});
    }
    moveProps(scene.props, propMoves);
    frame.propsMoved();
    scene.sun.direction = daySun(static_cast<double>(i) / options.length.frames);

    const double time = i / 30.0;
    const auto frameStart = Clock::now();
    const render::FrameStats s = frame.render(path[static_cast<size_t>(i)], time, settings);
    const double ms = 1e3 * std::chrono::duration<double>(Clock::now() - frameStart).count();
    geometryByFrame[static_cast<size_t>(i)] = s.passMs[FramePass::Geometry];
    takeGeometryTimes(frame.takePassTimes());
    if (options.checkEvery > 0 && i % options.checkEvery == options.checkEvery - 1) {
      mismatched += pixelsUnlikeFrustumCulling(frame, path[static_cast<size_t>(i)], time);
      ++checks;
    }
    if (i >= options.length.warmup) {
      frameMs.push_back(ms);
      trianglesGeometry.push_back(s.geometryTriangles);
      trianglesShadow.push_back(s.shadowTriangles);
      queries.push_back(s.culling.queriesIssued);
      rss.push_back(residentMegabytes());
      heap.push_back(heapInUseMegabytes());
    }
    ++done;
    showProgress("stress", "frames", done, total, std::chrono::duration<double>(Clock::now() - start).count(), options.length.quiet);
  }
  takeGeometryTimes(frame.drainPassTimes());
  const std::vector<double> geometryMs(geometryByFrame.begin() + std::min(options.length.warmup, options.length.frames), geometryByFrame.end());
  if (gl::debugErrorCount() > 0)
    throw Error(fmt::format("{} GL errors during the stress run (first: {})", gl::debugErrorCount(), gl::debugErrorMessages().front()));
  auto asDouble = [](const std::vector<long long>& v) { return std::vector<double>(v.begin(), v.end()); };
  const double p50 = percentile(frameMs, 0.5);
  RunResult r;
  r.frameP50 = p50;
  r.mismatched = mismatched;
  r.json = {{"trees", treeCount},
            {"lod0_triangles", lod0},
            {"terrain_size_m", scene.terrain->size},
            {"frames", options.length.frames},
            {"frame_ms", {{"p50", p50}, {"p95", percentile(frameMs, 0.95)}, {"max", frameMs.empty() ? 0.0 : *std::max_element(frameMs.begin(), frameMs.end())}}},
            {"max_over_median", p50 > 0.0 && !frameMs.empty() ? *std::max_element(frameMs.begin(), frameMs.end()) / p50 : 0.0},
            {"geometry_ms_p50", percentile(geometryMs, 0.5)},
            {"triangles_geometry_p50", percentile(asDouble(trianglesGeometry), 0.5)},
            {"triangles_shadow_p50", percentile(asDouble(trianglesShadow), 0.5)},
            {"queries_p50", percentile(asDouble(queries), 0.5)},
            {"moved_trees_per_frame", movedPerFrame},
            {"moved_props_per_frame", kProps},
            {"exactness", {{"checked_frames", checks}, {"mismatched_pixels", mismatched}}},
            {"rss_mib", memoryTrend(rss)},
            {"heap_in_use_mib", memoryTrend(heap)}};
  return r;
}

// The runs' table, for the console (aligned columns) or stress.md (Markdown).
std::string stressTable(const ordered_json& runs, bool markdown) {
  struct Column {
    const char* heading;
    int width;
    std::function<std::string(const ordered_json&)> cell;
  };
  const auto number = [](const char* format, auto get) {
    return [format, get](const ordered_json& r) { return fmt::format(fmt::runtime(format), get(r)); };
  };
  const auto slopeCell = [](const char* series) {  // "-" where the run was too short for a slope
    return [series](const ordered_json& r) {
      const ordered_json& v = r[series]["slope_percent_per_100_frames"];
      return v.is_null() ? std::string("-") : fmt::format("{:+.2f}", v.get<double>());
    };
  };
  const std::vector<Column> columns{
      {"trees", 7, number("{}", [](const ordered_json& r) { return r["trees"].get<int>(); })},
      {"lod0", 6, number("{}", [](const ordered_json& r) { return r["lod0_triangles"].get<int>(); })},
      {"p50 ms", 9, number("{:.1f}", [](const ordered_json& r) { return r["frame_ms"]["p50"].get<double>(); })},
      {"p95 ms", 9, number("{:.1f}", [](const ordered_json& r) { return r["frame_ms"]["p95"].get<double>(); })},
      {"max/p50", 9, number("{:.2f}", [](const ordered_json& r) { return r["max_over_median"].get<double>(); })},
      {"geom ms", 8, number("{:.1f}", [](const ordered_json& r) { return r["geometry_ms_p50"].get<double>(); })},
      {"eye tris", 11, number("{:.0f}", [](const ordered_json& r) { return r["triangles_geometry_p50"].get<double>(); })},
      {"shadow tris", 11, number("{:.0f}", [](const ordered_json& r) { return r["triangles_shadow_p50"].get<double>(); })},
      {"queries", 8, number("{:.0f}", [](const ordered_json& r) { return r["queries_p50"].get<double>(); })},
      {"exactness", 16, [](const ordered_json& r) {
         const long long px = r["exactness"]["mismatched_pixels"].get<long long>();
         const int checked = r["exactness"]["checked_frames"].get<int>();
         if (checked == 0) return std::string("not checked");
         return px == 0 ? fmt::format("exact, {} fr", checked) : fmt::format("{} px, {} fr", px, checked);
       }},
      {"RSS %/100f", 11, slopeCell("rss_mib")},
      {"heap %/100f", 11, slopeCell("heap_in_use_mib")}};
  std::string table = markdown ? "|" : " ";
  for (const Column& c : columns) table += markdown ? fmt::format(" {} |", c.heading) : fmt::format(" {:>{}}", c.heading, c.width);
  table += "\n";
  if (markdown) {
    table += "|";
    for (size_t i = 0; i < columns.size(); ++i) table += "---:|";
    table += "\n";
  }
  for (const ordered_json& r : runs) {
    table += markdown ? "|" : " ";
    for (const Column& c : columns) table += markdown ? fmt::format(" {} |", c.cell(r)) : fmt::format(" {:>{}}", c.cell(r), c.width);
    table += "\n";
  }
  return table;
}

// What a run of `frames` frames (`warmup` of them warm-up) is too short for: empty when nothing.
std::string shortRunWarning(int frames, int warmup, int checkEvery) {
  const int measured = frames - warmup;
  const int checked = checkEvery > 0 ? frames / checkEvery : 0;
  std::vector<std::string> missing;
  if (measured < kMinSlopeFrames)
    missing.push_back(fmt::format("{} measured frames are too few for the memory slopes (they need {}; left out)", measured, kMinSlopeFrames));
  if (checkEvery > 0 && checked < kMinCheckedFrames)
    missing.push_back(checked == 0 ? fmt::format("no frame is checked for exactness (every {}th is)", checkEvery)
                                   : fmt::format("exactness is checked on {} frame{} only", checked, checked == 1 ? "" : "s"));
  if (missing.empty()) return {};
  const int enough = std::max(warmup + kMinSlopeFrames, checkEvery * kMinCheckedFrames);
  return fmt::format("{} frames per run ({} warm-up): {}; --frames {} or more measures both", frames, warmup, fmt::join(missing, ", "), enough);
}

int runStress(const StressOptions& given) {
  StressOptions options = given;
  options.length.warmup = given.length.warmupFor(given.length.frames);  // the default: at most half of a shorter run
  const std::string scenePath = sceneFileOr(options.scene);
  for (int n : options.trees)
    if (n < 1 || n > 1000000) throw InputError(fmt::format("--trees {}: expected 1 to 1000000", n));
  for (int l : options.lod0)
    if (l < 1000 || l > 20000) throw InputError(fmt::format("--lod0 {}: expected 1000 to 20000 triangles", l));
  if (options.length.frames <= options.length.warmup) throw InputError(fmt::format("--frames {}: expected more than --warmup {}", options.length.frames, options.length.warmup));
  const std::string shortRun = shortRunWarning(options.length.frames, options.length.warmup, options.checkEvery);
  if (!shortRun.empty()) std::cerr << "stress: warning: " << shortRun << "\n";
  const Scene base = loadScene(scenePath);
  const std::filesystem::path out = options.out;
  std::filesystem::create_directories(out);
  // RSS shows live memory, not glibc's trimming: main() keeps freed heap in the process
  // (keepFreedHeapMemory), so RSS is the high-water mark and grows only with a leak or a growing
  // working set. (Sanitizer builds have their own allocator.)

  auto context = options.gl.open(options.size.width, options.size.height);

  const int total = static_cast<int>(options.trees.size() * options.lod0.size()) * options.length.frames;
  int done = 0;
  const auto start = Clock::now();
  ordered_json runs = ordered_json::array();
  long long mismatched = 0;
  PlotPanel frameTime{"frame time", "trees", "p50 frame ms", {}}, geometry{"geometry pass (culling + drawing)", "trees", "p50 ms", {}},
      triangles{"triangles", "trees", "p50 per frame (millions)", {}}, queryPanel{"occlusion queries", "trees", "p50 per frame", {}};
  for (int lod0 : options.lod0) {
    const glm::vec3 colour = lod0 == options.lod0.front() ? glm::vec3(0.15f, 0.45f, 0.85f) : glm::vec3(0.85f, 0.3f, 0.15f);
    PlotSeries ft{fmt::format("LOD0 {}", lod0), colour, {}, true}, gm = ft, tg = ft, q = ft;
    for (int trees : options.trees) {
      const RunResult r = runOne(base, trees, lod0, options, context->info(), done, total, start);
      mismatched += r.mismatched;
      const double n = r.json["trees"].get<double>();
      ft.points.emplace_back(n, r.json["frame_ms"]["p50"].get<double>());
      gm.points.emplace_back(n, r.json["geometry_ms_p50"].get<double>());
      tg.points.emplace_back(n, (r.json["triangles_geometry_p50"].get<double>() + r.json["triangles_shadow_p50"].get<double>()) / 1e6);
      q.points.emplace_back(n, r.json["queries_p50"].get<double>());
      runs.push_back(r.json);
    }
    frameTime.series.push_back(ft);
    geometry.series.push_back(gm);
    triangles.series.push_back(tg);
    queryPanel.series.push_back(q);
  }
  ordered_json report{{"scene", scenePath}, {"device", gl::describe(context->info())}, {"resolution", {options.size.width, options.size.height}},
                      {"settings", options.frame.json(context->info(), base)},
                      {"frames", options.length.frames}, {"warmup", options.length.warmup}, {"moving_share", options.moving},
                      {"check_every", options.checkEvery}, {"runs", runs}};
  writeFileAtomic(out / "stress.json", report.dump(2) + "\n");
  writeImage(out / "stress.png", plotPanels({frameTime, geometry, triangles, queryPanel}, 2));

  std::cout << fmt::format("stress: {} at {}x{}, {} frames per run ({} warm-up), {:.0f}% of the trees and {} props moved per frame, day cycle\n",
                           scenePath, options.size.width, options.size.height, options.length.frames, options.length.warmup, 100 * options.moving, kProps);
  std::cout << stressTable(runs, false);
  writeFileAtomic(out / "stress.md", fmt::format("# Dynamic scenes (forest stress)\n\n{}\n\n{} at {}x{}, {} frames per run ({} warm-up), "
                                                 "{:.0f}% of the trees and {} props moved per frame, a day cycle.\n\n{}",
                                                 benchmarkStamp(gl::describe(context->info())), scenePath, options.size.width,
                                                 options.size.height, options.length.frames, options.length.warmup, 100 * options.moving, kProps,
                                                 stressTable(runs, true)) +
                                         (shortRun.empty() ? std::string() : "\nToo short: " + shortRun + ".\n"));
  std::cout << fmt::format("  wrote {0}/stress.json, {0}/stress.md and {0}/stress.png\n", shownPath(out));
  if (mismatched > 0) std::cerr << fmt::format("stress: culling was not exact: {} pixels differ from frustum culling\n", mismatched);
  return mismatched == 0 ? 0 : 1;
}

}  // namespace

Run addStressCommand(CLI::App& app) {
  auto options = std::make_shared<StressOptions>();
  CLI::App* command = app.add_subcommand(
      "stress",
      "Polygon-rich dynamic scenes: for each tree count (terrain grown to keep the density) and LOD0 budget, a walk\n"
      "with a share of the trees and 20 props moved every frame (BVH refit), a day cycle of the sun and wind;\n"
      "frame time, geometry pass, triangles, queries, RSS and heap in use per run, and on sampled frames the culled geometry pass\n"
      "(depth and object IDs) against frustum culling's. Writes stress.json (fields: docs/report-format.md) stress.md and stress.png; exit 1 if not exact.");
  options->gl.add(*command);
  command->add_option("--scene", options->scene, "Base scene (default: data/scenes/forest.toml)");
  command->add_option("--out", options->out, "Output folder (created when missing)")->check(outputFolder())->capture_default_str();
  command->add_option("--trees", options->trees, "Tree counts (comma-separated, 1 to 10^6)")
      ->delimiter(',')
      ->check(CLI::Range(1, 1000000))
      ->capture_default_str();
  command->add_option("--lod0", options->lod0, "LOD0 triangle budgets per tree (comma-separated, 1000 to 20000)")
      ->delimiter(',')
      ->check(CLI::Range(1000, 20000))
      ->capture_default_str();
  options->size.add(*command);
  options->length.add(*command, "300 per run");
  options->frame.add(*command);
  command->add_option("--moving", options->moving, "Share of the trees moved every frame (0 to 1)")->check(CLI::Range(0.0, 1.0))->capture_default_str();
  command->add_option("--check-every", options->checkEvery, "Frames between exactness checks (0 to 10^6; 0: none)")
      ->check(CLI::Range(0, 1000000))
      ->capture_default_str();
  return [options] { return runStress(*options); };
}

}  // namespace forest::app
