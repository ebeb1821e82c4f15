// forest bench speed-error's outputs (docs/speed-error.md): report.json, results.csv, table.md (the
// error and time per layout, the error by distance, flicker), plots of time against each error
// figure with the Pareto front.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "forest/core/files.hpp"
#include "forest/core/image.hpp"
#include "forest/core/plot.hpp"
#include "run_output.hpp"
#include "speed_error.hpp"

namespace forest::app {
namespace {

using nlohmann::ordered_json;

const glm::vec3 kMethodColour[] = {{0.85f, 0.2f, 0.15f}, {0.95f, 0.6f, 0.1f}, {0.15f, 0.45f, 0.85f}, {0.2f, 0.65f, 0.3f}};

// A method's colour; its cascaded layouts darker.
glm::vec3 seriesColour(const std::string& method, int cascades) {
  const auto it = std::find(kSpeedErrorMethods.begin(), kSpeedErrorMethods.end(), method);
  const glm::vec3 c = kMethodColour[static_cast<size_t>(it - kSpeedErrorMethods.begin()) % std::size(kMethodColour)];  // a new method reuses a colour
  return cascades == 1 ? c : 0.55f * c;
}

// The series the sweep has: each method, one map and each K swept.
std::vector<std::pair<std::string, int>> allSeries(const std::vector<MapLayout>& layouts) {
  std::vector<int> ks;
  for (const MapLayout& l : layouts)
    if (std::find(ks.begin(), ks.end(), l.cascades) == ks.end()) ks.push_back(l.cascades);
  std::vector<std::pair<std::string, int>> series;
  for (int k : ks)
    for (const std::string& method : kSpeedErrorMethods) series.emplace_back(method, k);
  return series;
}

const Row* findRow(const std::vector<Row>& rows, const std::string& scenario, const std::string& method, int cascades, int totalSide) {
  for (const Row& r : rows)
    if (r.scenario == scenario && r.method == method && r.focus == "receivers" && r.layout.cascades == cascades &&
        r.layout.totalSide == totalSide && r.blur)
      return &r;
  return nullptr;
}

// One image: a panel per scenario, frame (or shadow-pass) ms against an error figure, a series per
// method and layout kind, the Pareto front in black.
void writePlot(const std::filesystem::path& file, const std::vector<Scenario>& scenarios, const std::vector<MapLayout>& layouts,
               const std::vector<Row>& rows, const std::string& xLabel, double (*x)(const Row&), bool shadowPass) {
  std::vector<PlotPanel> panels;
  for (const Scenario& s : scenarios) {
    PlotPanel panel;
    panel.title = s.name;
    panel.xLabel = xLabel;
    panel.yLabel = shadowPass ? "shadow pass ms" : "frame ms";
    std::vector<glm::dvec2> all;
    for (const auto& [method, k] : allSeries(layouts)) {
      PlotSeries series{seriesName(method, k), seriesColour(method, k), {}, false};
      for (const Row& r : rows)
        if (r.scenario == s.name && r.method == method && r.layout.cascades == k)
          series.points.emplace_back(x(r), shadowPass ? r.shadowMs : r.frameMs);
      all.insert(all.end(), series.points.begin(), series.points.end());
      panel.series.push_back(std::move(series));
    }
    panel.series.push_back({"Pareto front", glm::vec3(0.0f), paretoFront(all), true});
    panels.push_back(std::move(panel));
  }
  writeImage(file, plotPanels(panels, std::min<int>(4, static_cast<int>(panels.size()))));
}

std::string bandName(const truth::DistanceBand& b) {
  return std::isinf(b.toM) ? fmt::format("{:.0f} m+", b.fromM) : fmt::format("{:.0f}–{:.0f} m", b.fromM, b.toM);
}

// What every part of the report reads.
struct ReportInputs {
  const SpeedErrorOptions& options;
  const std::string& scenePath;
  const std::string& device;
  const ordered_json& modes;
  int width, height;
  const std::vector<Scenario>& scenarios;
  const std::vector<MapLayout>& layouts;
  const std::vector<Row>& rows;
  const std::vector<FlickerRow>& flicker;
  std::vector<int> totals;                            // total sides, in sweep order
  std::vector<std::pair<std::string, int>> series;    // method and K
};

// Equal-error sizes: per scenario, method and K (B from the receivers), the smallest total side
// whose misclassification is at most the target.
ordered_json equalErrorSizes(const ReportInputs& in) {
  ordered_json equalError;
  for (const Scenario& s : in.scenarios)
    for (const auto& [method, k] : in.series) {
      ordered_json size = nullptr;
      for (int total : in.totals)
        if (const Row* r = findRow(in.rows, s.name, method, k, total); r && r->error.misclassification <= in.options.target) {
          size = total;
          break;
        }
      equalError[s.name][seriesName(method, k)] = size;
    }

  return equalError;
}

// report.json's content and results.csv's.
std::pair<ordered_json, std::string> reportJsonAndCsv(const ReportInputs& in, const ordered_json& equalError) {
  ordered_json report;
  report["version"] = 2;
  report["scene"] = in.scenePath;
  report["device"] = in.device;
  report.update(in.modes);
  report["resolution"] = {in.width, in.height};
  report["quick"] = in.options.quick;
  report["map_sizes"] = in.totals;
  report["cascades"] = in.options.cascades;
  report["far_slice_scale"] = in.options.farSliceScale;
  report["soft_rays"] = in.options.softRays;
  report["target_misclassification"] = in.options.target;
  report["scenarios"] = ordered_json::array();
  for (const Scenario& s : in.scenarios)
    report["scenarios"].push_back({{"name", s.name},
                                   {"camera", {s.camera.position.x, s.camera.position.y, s.camera.position.z}},
                                   {"yaw_deg", glm::degrees(s.camera.yaw)},
                                   {"pitch_deg", glm::degrees(s.camera.pitch)},
                                   {"sun_direction", {s.sun.x, s.sun.y, s.sun.z}}});
  std::ostringstream csv;
  csv << "scenario,method,focus,cascades,map_size,total_texels,blur,frame_ms,shadow_ms,shadow_triangles,misclassification,near_edge,"
         "elsewhere,false_shadow,false_light,band_0_50,band_50_200,band_200_plus,soft_mae,aliasing_p95_px,aliasing_max_px,"
         "casters_selected,casters_needed,casters_missing,casters_needed_triangles\n";
  report["rows"] = ordered_json::array();
  for (const Row& r : in.rows) {
    const truth::FrameError& e = r.error;
    const long long texels = r.layout.texels();
    report["rows"].push_back({{"scenario", r.scenario},
                              {"method", r.method},
                              {"focus", r.focus},
                              {"cascades", r.layout.cascades},
                              {"map_size", r.layout.layerSize},
                              {"far_map_size", r.layout.farSize()},
                              {"total_texels", texels},
                              {"blur", r.blur},
                              {"frame_ms", r.frameMs},
                              {"shadow_ms", r.shadowMs},
                              {"shadow_triangles", r.shadowTriangles},
                              {"misclassification", e.misclassification},
                              {"near_edge", e.misclassificationNearEdge},
                              {"elsewhere", e.misclassificationElsewhere},
                              {"false_shadow", e.falseShadow},
                              {"false_light", e.falseLight},
                              {"bands", bandsJson(e.bands)},
                              {"soft_mae", in.options.softRays > 0 ? ordered_json(r.softError) : ordered_json()},
                              {"aliasing_p95_px", e.aliasingPixels.p95},
                              {"aliasing_max_px", e.aliasingPixels.max},
                              {"lit_facing_pixels", e.litFacing},
                              {"casters_selected", e.casters.selected},
                              {"casters_needed", e.casters.needed},
                              {"casters_missing", e.casters.missing},
                              {"casters_needed_triangles", e.casters.neededTriangles}});
    auto band = [&](size_t i) { return i < e.bands.size() ? e.bands[i].misclassification : 0.0; };
    csv << fmt::format("\"{}\",{},{},{},{},{},{},{:.3f},{:.3f},{},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.4f},{:.4f},{},{},{},{}\n",
                       r.scenario, r.method, r.focus, r.layout.cascades, r.layout.layerSize, texels, r.blur ? 1 : 0, r.frameMs,
                       r.shadowMs, r.shadowTriangles, e.misclassification, e.misclassificationNearEdge, e.misclassificationElsewhere,
                       e.falseShadow, e.falseLight, band(0), band(1), band(2), r.softError, e.aliasingPixels.p95, e.aliasingPixels.max,
                       e.casters.selected, e.casters.needed, e.casters.missing, e.casters.neededTriangles);
  }
  report["flicker"] = ordered_json::array();
  for (const FlickerRow& f : in.flicker) {
    const CachedWalk& c = f.cached;
    auto passJson = [&](const WalkPass& p) {
      return ordered_json{{"layers", {{"reused", p.reused}, {"added", p.added}, {"redrawn", p.redrawn}}},
                          {"shadow_triangles", p.triangles},
                          {"last_view", {{"misclassification", p.lastView.misclassification}, {"bands", bandsJson(p.lastView.bands)}}}};
    };
    const ordered_json cached = !c.measured ? ordered_json(nullptr)
                                            : ordered_json{{"redrawn", passJson(c.redrawn)}, {"cached", passJson(c.cached)},
                                                           {"staggered", passJson(c.staggered)}};
    report["flicker"].push_back({{"method", f.method},
                                 {"focus", f.focus},
                                 {"cascades", f.layout.cascades},
                                 {"map_size", f.layout.layerSize},
                                 {"far_map_size", f.layout.farSize()},
                                 {"share", f.result.share()},
                                 {"probes", f.result.probes},
                                 {"comparisons", f.result.comparisons},
                                 {"changes", f.result.changes},
                                 {"keep_slices", f.keep},
                                 {"kept_share", f.result.slices ? static_cast<double>(f.result.slicesKept) / f.result.slices : 0.0},
                                 {"last_view", {{"misclassification", f.lastView.misclassification},
                                                {"bands", bandsJson(f.lastView.bands)},
                                                {"shadow_triangles", f.lastViewShadowTriangles}}},
                                 {"cached_walk", cached}});
  }
  report["equal_error_map_size"] = equalError;

  return {report, csv.str()};
}

// The flicker walk of a series at a total size, B from the receivers, with or without kept slices.
const FlickerRow* findFlicker(const std::vector<FlickerRow>& flicker, const std::string& method, int cascades, int totalSide, bool keep) {
  for (const FlickerRow& f : flicker)
    if (f.method == method && f.focus == "receivers" && f.layout.cascades == cascades && f.layout.totalSide == totalSide && f.keep == keep)
      return &f;
  return nullptr;
}

// The head of a table with a column per total size.
void totalsHeader(std::ostringstream& md, const std::vector<int>& totals) {
  md << "| method |";
  for (int total : totals) md << fmt::format(" {}² |", total);
  md << "\n|---|";
  for (size_t i = 0; i < totals.size(); ++i) md << "---|";
  md << "\n";
}

// table.md: misclassification and frame time per layout, by distance band, and flicker.
std::string markdownTables(const ReportInputs& in, const ordered_json& equalError) {
  std::ostringstream md;
  md << benchmarkStamp(in.device) << "\n\n";
  md << fmt::format("Speed against error: {} at {}x{}, B from the visible receivers, blur 3 px, casters {} ({}). Layouts at "
                    "equal total texels: one map of N², or K slices of (N/√K)² (\"xK\").\n\n"
                    "Misclassified lit-facing pixels (%) / frame ms, per total texels N²:\n\n",
                    std::filesystem::path(in.scenePath).filename().string(), in.width, in.height, in.modes.value("casters", std::string("?")), in.device);
  md << "| scenario | method |";
  for (int total : in.totals) md << fmt::format(" {}² |", total);
  md << " equal-error size (≤ " << 100 * in.options.target << "%) |\n|---|---|";
  for (size_t i = 0; i <= in.totals.size(); ++i) md << "---|";
  md << "\n";
  for (const Scenario& s : in.scenarios)
    for (const auto& [method, k] : in.series) {
      md << "| " << s.name << " | " << seriesName(method, k) << " |";
      for (int total : in.totals) {
        const Row* r = findRow(in.rows, s.name, method, k, total);
        md << (r ? fmt::format(" {:.2f} / {:.0f} |", 100 * r->error.misclassification, r->frameMs) : std::string(" – |"));
      }
      const ordered_json& e = equalError[s.name][seriesName(method, k)];
      md << " " << (e.is_null() ? std::string("> ") + std::to_string(in.totals.back()) : std::to_string(e.get<int>())) << " |\n";
    }

  // By distance, at 2048² total texels when swept (else the largest total).
  const int bandTotal = std::find(in.totals.begin(), in.totals.end(), 2048) != in.totals.end() ? 2048 : in.totals.back();
  md << fmt::format("\nBy distance from the eye at {}² total texels: misclassified lit-facing pixels (%) per band; the "
                    "shadow pass's triangles (all layers), the triangles of the casters the truth needs (the first "
                    "occluder of each lit-facing pixel) and the ratio of the two:\n\n| scenario | method |",
                    bandTotal);
  const Row* any = findRow(in.rows, in.scenarios.front().name, in.series.front().first, in.series.front().second, bandTotal);
  const size_t bandCount = any ? any->error.bands.size() : 0;
  for (size_t b = 0; b < bandCount; ++b) md << " " << bandName(any->error.bands[b]) << " |";
  md << " shadow triangles | needed | drawn / needed |\n|---|---|";
  for (size_t b = 0; b < bandCount + 3; ++b) md << "---|";
  md << "\n";
  for (const Scenario& s : in.scenarios)
    for (const auto& [method, k] : in.series) {
      const Row* r = findRow(in.rows, s.name, method, k, bandTotal);
      if (!r) continue;
      md << "| " << s.name << " | " << seriesName(method, k) << " |";
      for (const truth::DistanceBand& b : r->error.bands) md << fmt::format(" {:.2f} |", 100 * b.misclassification);
      const long long needed = r->error.casters.neededTriangles;
      md << fmt::format(" {} | {} | {} |\n", r->shadowTriangles, needed,
                        needed > 0 ? fmt::format("{:.2f}", static_cast<double>(r->shadowTriangles) / static_cast<double>(needed)) : std::string("–"));
    }

  md << "\nFlicker (share of probe states that change between consecutive frames, " << in.scenarios.front().name
     << ", walking 0.4 m and turning 0.3 deg per frame), B from the receivers, per total texels; with kept slices\n"
        "(--keep-slices on) the share of slices that kept their map, and the misclassification (%) of the walk's\n"
        "last view off / on:\n\n";
  totalsHeader(md, in.totals);
  for (const auto& [method, k] : in.series)
    for (bool keep : {false, true}) {
      std::string line = "| " + seriesName(method, k) + (keep ? " kept" : "") + " |";
      bool measured = false;
      for (int total : in.totals) {
        const FlickerRow* f = findFlicker(in.flicker, method, k, total, keep);
        const FlickerRow* off = findFlicker(in.flicker, method, k, total, false);
        measured = measured || f != nullptr;
        line += !f ? " – |"
               : !keep ? fmt::format(" {:.4f} |", f->result.share())
                       : fmt::format(" {:.4f} ({:.0f}% kept; {:.2f} / {:.2f}) |", f->result.share(),
                                     100.0 * f->result.slicesKept / std::max(f->result.slices, 1), 100 * off->lastView.misclassification,
                                     100 * f->lastView.misclassification);
      }
      if (measured) md << line << "\n";
    }

  md << "\nCached slices on the same walk with the trees swaying (30 frames a second), kept slices: the share of\n"
        "layers reused or added to (not cleared) over the walk and its shadow triangles against redrawing every\n"
        "frame, cached (--cache-slices on) / staggered (--cache-slices staggered); the misclassification (%) of\n"
        "the last view redrawn / cached / staggered, per total texels:\n\n";
  totalsHeader(md, in.totals);
  for (const auto& [method, k] : in.series) {
    std::string line = "| " + seriesName(method, k) + " |";
    bool measured = false;
    for (int total : in.totals) {
      const FlickerRow* f = findFlicker(in.flicker, method, k, total, true);
      if (!f || !f->cached.measured) {
        line += " – |";
        continue;
      }
      measured = true;
      const CachedWalk& c = f->cached;
      auto kept = [](const WalkPass& p) { return 100.0 * (p.reused + p.added) / std::max(p.reused + p.added + p.redrawn, 1); };
      auto triangles = [&](const WalkPass& p) { return static_cast<double>(p.triangles) / static_cast<double>(std::max(c.redrawn.triangles, 1LL)); };
      line += fmt::format(" {:.0f}% / {:.0f}% not cleared, {:.2f}x / {:.2f}x triangles; {:.2f} / {:.2f} / {:.2f} |", kept(c.cached),
                          kept(c.staggered), triangles(c.cached), triangles(c.staggered), 100 * c.redrawn.lastView.misclassification,
                          100 * c.cached.lastView.misclassification, 100 * c.staggered.lastView.misclassification);
    }
    if (measured) md << line << "\n";
  }
  return md.str();
}

// The plots: frame or shadow ms against each error figure, and against flicker, with the Pareto front.
void writePlots(const std::filesystem::path& out, const ReportInputs& in) {
  writePlot(out / "frame-ms-vs-misclassification.png", in.scenarios, in.layouts, in.rows, "misclassified pixels (share)",
            [](const Row& r) { return r.error.misclassification; }, false);
  writePlot(out / "shadow-ms-vs-misclassification.png", in.scenarios, in.layouts, in.rows, "misclassified pixels (share)",
            [](const Row& r) { return r.error.misclassification; }, true);
  if (in.options.softRays > 0)  // --soft-rays 0: no soft truth, no plot of it
    writePlot(out / "frame-ms-vs-soft-error.png", in.scenarios, in.layouts, in.rows, "mean |term - soft truth|",
              [](const Row& r) { return r.softError; }, false);
  writePlot(out / "frame-ms-vs-aliasing.png", in.scenarios, in.layouts, in.rows, "aliasing p95 (px per texel)",
            [](const Row& r) { return r.error.aliasingPixels.p95; }, false);
  PlotPanel panel;
  panel.title = "flicker, " + in.scenarios.front().name + " (moving camera)";
  panel.xLabel = "share of probes changing state per frame";
  panel.yLabel = "frame ms";
  std::vector<glm::dvec2> all;
  for (const auto& [method, k] : in.series) {
    for (bool keep : {false, true}) {
      PlotSeries s{seriesName(method, k) + (keep ? " kept" : ""), seriesColour(method, k) * (keep ? 0.6f : 1.0f), {}, false};
      for (const FlickerRow& f : in.flicker)
        if (f.method == method && f.layout.cascades == k && f.keep == keep) s.points.emplace_back(f.result.share(), f.frameMs);
      if (s.points.empty()) continue;
      all.insert(all.end(), s.points.begin(), s.points.end());
      panel.series.push_back(std::move(s));
    }
  }
  panel.series.push_back({"Pareto front", glm::vec3(0.0f), paretoFront(all), true});
  writeImage(out / "frame-ms-vs-flicker.png", plotPanels({panel}, 1));
}

}  // namespace

std::string writeSpeedErrorReport(const std::filesystem::path& out, const SpeedErrorOptions& options, const std::string& scenePath,
                                  const std::string& device, const ordered_json& modes, int width, int height,
                                  const std::vector<Scenario>& scenarios, const std::vector<MapLayout>& layouts,
                                  const std::vector<Row>& rows, const std::vector<FlickerRow>& flicker) {
  ReportInputs in{options, scenePath, device, modes, width, height, scenarios, layouts, rows, flicker, {}, allSeries(layouts)};
  for (const MapLayout& l : layouts)
    if (std::find(in.totals.begin(), in.totals.end(), l.totalSide) == in.totals.end()) in.totals.push_back(l.totalSide);
  const ordered_json equalError = equalErrorSizes(in);
  const auto [report, csv] = reportJsonAndCsv(in, equalError);
  const std::string md = markdownTables(in, equalError);
  writeFileAtomic(out / "report.json", report.dump(2) + "\n");
  writeFileAtomic(out / "results.csv", csv);
  writeFileAtomic(out / "table.md", md);
  writePlots(out, in);
  return md;
}

}  // namespace forest::app
