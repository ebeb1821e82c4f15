// forest stability: every shadow method on hard and random configurations, with the invariants
// of issue "Shadow math I" checked on the float32 matrices the GPU gets. One JSON record per case
// and method (JSON Lines) for tools that check the matrices independently.
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>

#include "commands.hpp"
#include "forest/core/error.hpp"
#include "forest/core/files.hpp"
#include "forest/shadows/aliasing.hpp"
#include "forest/shadows/cascades.hpp"
#include "forest/shadows/stability.hpp"

namespace forest::app {
namespace {

using nlohmann::ordered_json;
using shadows::ShadowMethod;

struct StabilityOptions {
  std::string cases;
  std::uint64_t random = 0;
  std::uint64_t seed = 20061125;
  std::vector<std::string> methods = shadows::kShadowMethodNames.names();
  std::string out;
  bool json = false;
  bool aliasing = false;
  std::vector<int> screen{1280, 720};
  int cascades = 1;            // > 1: every slice of each case is a setup of its own (shadows::cascadeInputs)
  double splitLambda = 0.8;
  double cascadeBlend = 0.1;
};

ordered_json vec3(const glm::dvec3& v) { return {v.x, v.y, v.z}; }

ordered_json matrix(const glm::mat4& m) {
  ordered_json column_major = ordered_json::array();
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) column_major.push_back(m[c][r]);
  return column_major;
}

// The case in the case-file schema, so a failing random case can be saved and rerun alone.
ordered_json caseJson(const shadows::StabilityCase& c) {
  const shadows::ShadowInput& in = c.input;
  ordered_json j;
  j["name"] = c.name;
  j["eye"] = vec3(in.camera.position);
  j["view_dir"] = vec3(in.camera.forward());
  j["up"] = vec3(in.camera.up());
  j["fovy_deg"] = glm::degrees(in.camera.fovy);
  j["aspect"] = in.camera.aspect;
  j["near"] = in.camera.near;
  j["far"] = in.camera.far;
  j["sun_dir"] = vec3(in.sunDirection);
  j["scene_min"] = vec3(in.scene.min);
  j["scene_max"] = vec3(in.scene.max);
  if (in.receivers) j["receivers"] = ordered_json::array({{{"min", vec3(in.receivers->min)}, {"max", vec3(in.receivers->max)}}});
  if (in.nFar) j["n_far"] = *in.nFar;
  j["map_size"] = in.mapSize;
  j["border_texels"] = in.borderTexels;
  return j;
}

ordered_json recordJson(const shadows::StabilityCase& c, ShadowMethod method, int slice, const shadows::ShadowInput& input,
                        const shadows::ShadowSetup& setup, const shadows::StabilityReport& report,
                        const shadows::AliasingReport* aliasing) {
  const shadows::ShadowDiagnostics& d = setup.diagnostics;
  ordered_json j;
  j["case"] = c.name;
  j["method"] = shadows::kShadowMethodNames.name(method);
  if (slice >= 0) j["slice"] = {{"index", slice}, {"near", input.camera.near}, {"far", input.camera.far}};
  j["passed"] = report.passed();
  ordered_json invariants;
  for (const shadows::InvariantCheck& check : report.checks) invariants[check.name] = check.passed;
  j["invariants"] = invariants;
  for (const shadows::InvariantCheck& check : report.checks)
    if (!check.passed) j["failures"][check.name] = check.detail;
  j["empty"] = setup.empty;
  j["n"] = d.n;
  j["n_cap"] = d.nCap;
  j["warp"] = d.warp;
  j["gamma_deg"] = d.gammaDeg;
  j["z0"] = d.z0;
  j["z1"] = d.z1;
  j["d"] = d.d;
  j["fallback"] = d.fallback;
  j["body_vertices"] = d.bodyVertices;
  j["float_shrink"] = d.floatShrink;
  if (setup.linearDepth) {
    j["tsm"] = {{"lambda", d.tsmLambda}, {"focus", d.tsmFocus}, {"eta", d.tsmEta}, {"xi", d.tsmXi}, {"focus_area", d.tsmFocusArea}};
    const glm::vec4& r = setup.eyeRelativeToLightDepthF;
    j["eye_relative_to_light_depth"] = {r.x, r.y, r.z, r.w};  // tsm: depth = row · (p − eye, 1) (TSM §4)
  }
  j["max_map_coordinate"] = report.maxMapCoordinate;
  // world → [−1, 1]³ (x, y: map, z: depth away from the light), float32, column-major; and the
  // camera-relative form the GPU gets: clip = M · (p − eye, 1).
  j["world_to_shadow_clip"] = matrix(setup.worldToShadowClipF);
  j["eye_relative_to_shadow_clip"] = matrix(setup.eyeRelativeToShadowClipF);
  if (aliasing) {
    auto stats = [](const shadows::ErrorStatistics& e) {
      return ordered_json{{"max", e.max}, {"p95", e.p95}, {"mean", e.mean}, {"samples", e.samples}};
    };
    j["aliasing"] = {{"perspective_relative", stats(aliasing->perspective)},
                     {"perspective_px_per_texel", stats(aliasing->perspectivePixels)},
                     {"surface_px_per_texel", stats(aliasing->surfacePixels)},
                     {"log_floor_relative", aliasing->floor},
                     {"storage_factor", aliasing->storageFactor}};
  }
  j["input"] = caseJson(c);
  return j;
}

struct Tally {
  // refused: inputs outside the shadow domain (shadows::outsideShadowDomain), per case and method.
  std::uint64_t records = 0, failed = 0, empty = 0, warped = 0, refused = 0;
  double largestCoordinate = 0.0, largestShrink = 0.0, setupSeconds = 0.0;
  std::vector<std::string> firstFailures;
  // --aliasing: per method, per non-empty case: max perspective error (relative), its ratio to
  // the logarithmic floor, surface p95 (px per texel), storage factor.
  std::map<std::string, std::vector<std::array<double, 4>>> aliasing;
};

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

// Medians of the four aliasing columns of a method's rows.
std::array<double, 4> columnMedians(const std::vector<std::array<double, 4>>& rows) {
  std::array<double, 4> out{};
  for (int k = 0; k < 4; ++k) {
    std::vector<double> column;
    for (const auto& r : rows) column.push_back(r[k]);
    out[k] = median(std::move(column));
  }
  return out;
}

// The suite's run: every case (from the file, then the random stream) for every method, each
// setup checked (shadows::checkSetupInvariants) and tallied, a record per setup to `out`.
class StabilitySuite {
 public:
  StabilitySuite(const StabilityOptions& options, std::vector<ShadowMethod> methods) : options_(options), methods_(std::move(methods)) {}

  void runAll(const std::vector<shadows::StabilityCase>& fileCases, std::ostream* out) {
    for (const shadows::StabilityCase& c : fileCases) evaluate(c, out);
    const std::uint64_t step = std::max<std::uint64_t>(1, options_.random / 10);
    for (std::uint64_t i = 0; i < options_.random; ++i) {
      evaluate(shadows::randomStabilityCase(options_.seed, i), out);
      if (options_.random >= 10000 && (i + 1) % step == 0)
        std::cerr << fmt::format("stability: {}/{} random configurations, {} failed\n", i + 1, options_.random, tally_.failed);
    }
  }

  const Tally& tally() const { return tally_; }

 private:
  void noteFailure(std::string failure) {
    ++tally_.failed;
    if (tally_.firstFailures.size() < 10) tally_.firstFailures.push_back(std::move(failure));
  }

  // With --cascades K, each slice of the case's view (shadows::cascadeInputs) is a setup of its own.
  void evaluate(const shadows::StabilityCase& c, std::ostream* out) {
    std::vector<shadows::ShadowInput> inputs{c.input};
    if (options_.cascades > 1) {
      try {
        inputs = shadows::cascadeInputs(c.input, options_.cascades, options_.splitLambda, options_.cascadeBlend);
      } catch (const InputError& e) {  // a view the splits refuse (none inside the domain): refused like its setups
        tally_.records += methods_.size();
        tally_.refused += methods_.size();
        if (out) *out << ordered_json{{"case", c.name}, {"refused", e.what()}, {"input", caseJson(c)}}.dump() << '\n';
        return;
      }
    }
    for (size_t slice = 0; slice < inputs.size(); ++slice)
      for (ShadowMethod method : methods_) evaluateOne(c, inputs[slice], options_.cascades > 1 ? static_cast<int>(slice) : -1, method, out);
  }

  // One setup: a case's whole view, or one of its slices (slice ≥ 0). One case never stops the
  // suite: an input outside the domain is counted as refused, any other exception as a failure,
  // and either is written as a record.
  void evaluateOne(const shadows::StabilityCase& c, const shadows::ShadowInput& input, int slice, ShadowMethod method, std::ostream* out) {
    const std::string_view name = shadows::kShadowMethodNames.name(method);
    const std::string where = slice >= 0 ? fmt::format("{} (slice {})", c.name, slice) : c.name;
    ++tally_.records;
    std::optional<shadows::ShadowSetup> setup;
    try {
      const auto start = std::chrono::steady_clock::now();
      setup = shadows::computeShadowSetup(input, method);
      tally_.setupSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    } catch (const InputError& e) {
      ++tally_.refused;
      if (out) *out << ordered_json{{"case", where}, {"method", name}, {"refused", e.what()}, {"input", caseJson(c)}}.dump() << '\n';
      return;
    } catch (const std::exception& e) {
      noteFailure(fmt::format("{} / {}: exception: {}", where, name, e.what()));
      if (out)
        *out << ordered_json{{"case", where}, {"method", name}, {"passed", false}, {"failures", {{"exception", e.what()}}}, {"input", caseJson(c)}}.dump() << '\n';
      return;
    }
    const shadows::StabilityReport report = shadows::checkSetupInvariants(input, method, *setup);
    tally_.empty += setup->empty ? 1 : 0;
    tally_.warped += setup->diagnostics.warp > 0.0 ? 1 : 0;
    tally_.largestCoordinate = std::max(tally_.largestCoordinate, report.maxMapCoordinate);
    tally_.largestShrink = std::max(tally_.largestShrink, setup->diagnostics.floatShrink);
    if (!report.passed()) {
      for (const shadows::InvariantCheck& check : report.checks)
        if (!check.passed) {
          noteFailure(fmt::format("{} / {}: {}: {}", where, name, check.name, check.detail));
          break;
        }
    }
    std::optional<shadows::AliasingReport> aliasing;
    if (options_.aliasing && !setup->empty) {
      shadows::AliasingOptions aliasingOptions;
      aliasingOptions.width = options_.screen[0];
      aliasingOptions.height = options_.screen[1];
      aliasing = shadows::analyseAliasing(input, *setup, aliasingOptions);
      if (aliasing->perspective.samples > 0)
        tally_.aliasing[std::string(name)].push_back(
            {aliasing->perspective.max, aliasing->floor > 0.0 ? aliasing->perspective.max / aliasing->floor : 0.0,
             aliasing->surfacePixels.p95, aliasing->storageFactor});
    }
    if (out) *out << recordJson(c, method, slice, input, *setup, report, aliasing ? &*aliasing : nullptr).dump() << '\n';
  }

  const StabilityOptions& options_;
  const std::vector<ShadowMethod> methods_;
  Tally tally_;
};

// The suite's summary: JSON with --json, else a few lines (and the aliasing medians with --aliasing).
void printSummary(const StabilityOptions& options, const Tally& tally, std::size_t fileCases) {
  const double microseconds = tally.records ? 1e6 * tally.setupSeconds / static_cast<double>(tally.records) : 0.0;
  if (options.json) {
    ordered_json summary;
    summary["records"] = tally.records;
    summary["failed"] = tally.failed;
    summary["refused"] = tally.refused;
    summary["empty"] = tally.empty;
    summary["warped"] = tally.warped;
    summary["largest_map_coordinate"] = tally.largestCoordinate;
    summary["largest_float_shrink"] = tally.largestShrink;
    summary["microseconds_per_setup"] = microseconds;
    summary["failures"] = tally.firstFailures;
    for (const auto& [method, rows] : tally.aliasing) {
      const std::array<double, 4> columns = columnMedians(rows);
      summary["aliasing_medians"][method] = {{"cases", rows.size()},
                                             {"perspective_max_relative", columns[0]},
                                             {"perspective_max_over_floor", columns[1]},
                                             {"surface_p95_px_per_texel", columns[2]},
                                             {"storage_factor", columns[3]}};
    }
    std::cout << summary.dump(2) << '\n';
    return;
  }
  std::cout << fmt::format(
      "{} setups ({} case(s) from file, {} random, seed {}, methods {}{}): {} failed, {} refused (outside the shadow domain)\n"
      "  largest |map coordinate| of B on the float32 path {:.9f}, largest float32 shrink {:.2e}\n"
      "  {} empty focus bodies, {} warped (lispsm), {:.1f} µs per setup\n",
      tally.records, fileCases, options.random, options.seed, fmt::join(options.methods, ","),
      options.cascades > 1 ? fmt::format(", {} slices each, λ {}", options.cascades, options.splitLambda) : std::string(), tally.failed,
      tally.refused, tally.largestCoordinate, tally.largestShrink, tally.empty, tally.warped, microseconds);
  if (!tally.aliasing.empty()) {
    std::cout << fmt::format("  aliasing, medians over cases ({}x{} screen):\n  {:<15} {:>6} {:>16} {:>12} {:>18} {:>14}\n",
                             options.screen[0], options.screen[1], "method", "cases", "persp. max (rel)", "max / floor",
                             "surface p95 px/tx", "storage factor");
    for (const auto& [method, rows] : tally.aliasing) {
      const std::array<double, 4> columns = columnMedians(rows);
      std::cout << fmt::format("  {:<15} {:>6} {:>16.3g} {:>12.3g} {:>18.3g} {:>14.3g}\n", method, rows.size(), columns[0],
                               columns[1], columns[2], columns[3]);
    }
  }
  if (!options.out.empty()) std::cout << fmt::format("  records: {}\n", options.out);
}

int runStability(const StabilityOptions& options) {
  if (options.cases.empty() && options.random == 0)
    throw InputError("stability: give --cases FILE and/or --random N");
  std::vector<ShadowMethod> methods;
  for (const std::string& name : options.methods) methods.push_back(shadows::kShadowMethodNames.parse(name));
  const std::vector<shadows::StabilityCase> fileCases =
      options.cases.empty() ? std::vector<shadows::StabilityCase>{} : shadows::loadStabilityCases(options.cases);

  StabilitySuite suite(options, std::move(methods));
  if (options.out.empty()) {
    suite.runAll(fileCases, nullptr);
  } else {
    writeAtomicallyWith(options.out, [&](const std::filesystem::path& temporary) {
      std::ofstream out(temporary);
      if (!out) throw Error(systemErrorMessage("cannot write " + temporary.string()));
      suite.runAll(fileCases, &out);
      out.close();
      if (!out) throw Error(systemErrorMessage("cannot write " + temporary.string()));
    });
  }
  printSummary(options, suite.tally(), fileCases.size());
  for (const std::string& failure : suite.tally().firstFailures) std::cerr << "stability: FAILED " << failure << '\n';
  return suite.tally().failed == 0 ? 0 : 1;
}

}  // namespace

Run addStabilityCommand(CLI::App& app) {
  auto options = std::make_shared<StabilityOptions>();
  CLI::App* command = app.add_subcommand(
      "stability",
      "Evaluate every shadow method on hard and random configurations and check the invariants\n"
      "(B inside the map with the float32 matrix, V ∩ S inside the map, 0 < n ≤ cap). Exit 1 if any\n"
      "fails, 2 for an invalid case file.");
  command->add_option("--cases", options->cases, "Case file (JSON), e.g. data/stability/hard-cases.json")
      ->check(CLI::ExistingFile);
  command->add_option("--random", options->random, "Number of random configurations to add (0 to 10^8)")->check(CLI::Range(0, 100000000));
  command->add_option("--seed", options->seed, "Seed of the random configurations")->capture_default_str();
  command->add_option("--methods", options->methods, "Methods to evaluate (comma-separated)")
      ->delimiter(',')
      ->check(CLI::IsMember(shadows::kShadowMethodNames.names()))
      ->capture_default_str();
  command->add_option("--out", options->out,
                      "Write one JSON record per case and method (JSON Lines): diagnostics, invariants, the\n"
                      "float32 world → shadow-clip matrix (16 numbers, column-major) and the case itself; a file,\n"
                      "its folder must exist)")
      ->check(outputFile());
  command->add_option("--cascades", options->cascades,
                      "Z-partitioning: split each case's view [near, far] into K slices (Zhang et al. 2006 eq. 4)\n"
                      "and check every invariant on every slice's setup (1 to 4; 1: the whole view)")
      ->check(CLI::Range(1, shadows::kMaxCascades))
      ->capture_default_str();
  command->add_option("--split-lambda", options->splitLambda, "Split scheme with --cascades (0 to 1): 1 logarithmic, 0 uniform")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  command->add_option("--cascade-blend", options->cascadeBlend, "Blend band beyond each split with --cascades (0 to 0.5)")
      ->check(CLI::Range(0.0, 0.5))
      ->capture_default_str();
  command->add_flag("--json", options->json, "Print the summary as JSON");
  command->add_flag("--aliasing", options->aliasing,
                    "Also compute the analytic aliasing error per setup (thesis eq. 8.1, 8.4; Lloyd's storage\n"
                    "factor) over sample points of V ∩ S: per record and as medians per method (slower)");
  command->add_option("--screen", options->screen, "Screen size in pixels for --aliasing (W H, each 1 to 16384)")
      ->expected(2)
      ->check(CLI::Range(1, 16384))
      ->capture_default_str();
  return [options] { return runStability(*options); };
}

}  // namespace forest::app
