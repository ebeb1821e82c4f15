// forest bench speed-error --quick: the documented report, rows at equal total texels (one map and
// four layers), bands that add up, plots with ink, the worst-case images. forest bench culling:
// every strategy and the oracle, ratios as printed, chc++'s batching against chc; a camera path file.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "cli_test_support.hpp"
#include "speed_error.hpp"
#include "forest/core/files.hpp"
#include "forest/core/image.hpp"
#include "test_paths.hpp"

namespace forest {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using Result = test::CliResult;
using test::runForest;

TEST(ForestCli, SpeedErrorQuickWritesTheDocumentedReportAndPlots) {
  const fs::path folder = fs::path(FOREST_TEST_OUTPUT) / "cli" / "speed-error";
  fs::remove_all(folder);
  const Result r = runForest("bench speed-error --quick --soft-rays 2 --out " + folder.string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("equal-error size"));
  const nlohmann::json j = nlohmann::json::parse(readTextFile(folder / "report.json"));
  for (const char* key : {"version", "scene", "device", "timing", "queries", "casters", "resolution", "quick", "map_sizes", "soft_rays",
                          "target_misclassification", "scenarios", "rows", "flicker", "equal_error_map_size", "far_slice_scale"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_EQ(j["timing"], "profile");           // auto on llvmpipe
  EXPECT_EQ(j["casters"], "receiver-pixels");  // auto on llvmpipe, as in every other command
  // 2 scenarios × 4 methods × (2 focus bounds at 1024², receivers at 4 × 512²) × blur on / off.
  ASSERT_EQ(j["rows"].size(), 48u);
  int cascaded = 0;
  for (const auto& row : j["rows"]) {
    for (const char* key : {"scenario", "method", "focus", "cascades", "map_size", "total_texels", "blur", "frame_ms", "shadow_ms",
                            "shadow_triangles", "misclassification", "near_edge", "elsewhere", "false_shadow", "false_light", "bands",
                            "soft_mae", "aliasing_p95_px", "aliasing_max_px", "lit_facing_pixels", "casters_selected", "casters_needed",
                            "casters_missing", "casters_needed_triangles"})
      ASSERT_TRUE(row.contains(key)) << key;
    // Equal total texels: one 1024² map or four 512² layers.
    EXPECT_EQ(row["total_texels"].get<long long>(), 1024LL * 1024);
    EXPECT_EQ(row["map_size"].get<int>(), row["cascades"].get<int>() == 4 ? 512 : 1024);
    EXPECT_EQ(row["far_map_size"], row["map_size"]);  // equal layers unless --far-slice-scale
    cascaded += row["cascades"].get<int>() == 4 ? 1 : 0;
    ASSERT_EQ(row["bands"].size(), 3u);
    int bandPixels = 0;
    for (const auto& band : row["bands"]) bandPixels += band["lit_facing"].get<int>();
    EXPECT_EQ(bandPixels, row["lit_facing_pixels"].get<int>());
    EXPECT_GT(row["frame_ms"].get<double>(), row["shadow_ms"].get<double>());
    EXPECT_GE(row["misclassification"].get<double>(), 0.0);
    EXPECT_LE(row["misclassification"].get<double>(), 1.0);
    EXPECT_NEAR(row["misclassification"].get<double>(), row["false_shadow"].get<double>() + row["false_light"].get<double>(), 1e-12);
    // casters_missing: crowns hidden from the sun are culled here (the term stays the term of all
    // casters: ReceiverPixelsGl); the receiver mask's own selection is checked in BenchScaleRuns….
    EXPECT_EQ(row["casters_needed_triangles"].get<long long>() > 0, row["casters_needed"].get<int>() > 0);  // a caster has triangles
  }
  EXPECT_EQ(cascaded, 16);
  // Flicker walks: 4 methods × 2 bounds at 1024² and 4 methods at 4 × 512², and again with kept
  // slices for the 3 methods that do not hold still by themselves (uniform-stable does).
  EXPECT_EQ(j["flicker"].size(), 12u + 9u);
  int keptWalks = 0;
  for (const auto& f : j["flicker"]) {
    const bool keep = f["keep_slices"].get<bool>();
    keptWalks += keep ? 1 : 0;
    EXPECT_FALSE(keep && f["method"] == "uniform-stable");
    const double share = f["kept_share"].get<double>();
    EXPECT_TRUE(keep ? share > 0.0 && share <= 1.0 : share == 0.0) << f["method"] << " " << share;
    EXPECT_GE(f["last_view"]["misclassification"].get<double>(), 0.0);
    EXPECT_EQ(f["last_view"]["bands"].size(), 3u);
    // Kept walks, again with the trees swaying, redrawn, cached and staggered: each layer of each of
    // the 16 frames was reused, added to or redrawn; redrawn every frame, never reused.
    const auto& cached = f["cached_walk"];
    ASSERT_EQ(cached.is_null(), !keep);
    if (!keep) continue;
    for (const char* pass : {"redrawn", "cached", "staggered"}) {
      const auto& layers = cached[pass]["layers"];
      EXPECT_EQ(layers["reused"].get<int>() + layers["added"].get<int>() + layers["redrawn"].get<int>(), 16 * f["cascades"].get<int>())
          << f["method"] << " " << pass;
      EXPECT_GE(cached[pass]["last_view"]["misclassification"].get<double>(), 0.0);
    }
    EXPECT_EQ(cached["redrawn"]["layers"]["redrawn"].get<int>(), 16 * f["cascades"].get<int>());
  }
  EXPECT_EQ(keptWalks, 9);
  for (const char* plot : {"frame-ms-vs-misclassification.png", "shadow-ms-vs-misclassification.png", "frame-ms-vs-soft-error.png",
                           "frame-ms-vs-aliasing.png", "frame-ms-vs-flicker.png"}) {
    const Image8 image = readImage8(folder / plot);
    int ink = 0;  // non-white pixels: axes, points, labels
    for (size_t i = 0; i < image.pixels.size(); i += 3) ink += image.pixels[i] < 200 ? 1 : 0;
    EXPECT_GT(ink, 2000) << plot;
  }
  EXPECT_FALSE(readTextFile(folder / "results.csv").empty());
  EXPECT_TRUE(fs::exists(folder / "worst-lispsm.png"));
  EXPECT_TRUE(fs::exists(folder / "worst-lispsm-x4.png"));
}

// In both timing and query modes (DESIGN §9): the profiled, deterministic default on llvmpipe and
// the GPU's timestamp queries with occlusion results read when available.
TEST(ForestCli, BenchCullingWritesEveryStrategyAndTheOracle) {
  const fs::path out = fs::path(FOREST_TEST_OUTPUT) / "cli" / "bench-culling";
  double chcPlusPlusGeometryQueries = 0.0;
  for (const auto& [timing, queries] : {std::pair{"profile", "deterministic"}, std::pair{"queries", "async"}}) {
    SCOPED_TRACE(std::string(timing) + " timing, " + queries + " queries");
    fs::remove_all(out);
    const Result r = runForest(fmt::format("bench culling --trees 300,600 --paths ground,hill --frames 4 --width 160 --height 90 "
                                           "--timing {} --queries {} --quiet --out {}", timing, queries, out.string()));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_THAT(r.out, HasSubstr("chc++ ground-path p50 frame, 600 trees over 300 trees"));
    EXPECT_THAT(r.out, HasSubstr("the oracle's one-frame lag: "));
    EXPECT_TRUE(fs::exists(out / "bench-culling.md"));
    EXPECT_GT(readImage8(out / "bench-culling.png").width, 0);
    const nlohmann::json j = nlohmann::json::parse(readTextFile(out / "bench-culling.json"));
    EXPECT_EQ(j["timing"], timing);
    EXPECT_EQ(j["queries"], queries);
    ASSERT_EQ(j["runs"].size(), 2u);
    for (const auto& [trees, paths] : j["runs"].items()) {
      ASSERT_EQ(paths.size(), 2u) << trees;
      for (const auto& [path, run] : paths.items()) {
        const auto& s = run["strategies"];
        for (const char* name : {"none", "frustum", "stop-and-wait", "chc", "chc++", "oracle"}) {
          ASSERT_TRUE(s.contains(name)) << trees << " " << path << " " << name;
          EXPECT_GT(s[name]["triangles_p50"].get<double>(), 0.0) << name;
          EXPECT_GT(s[name]["p50_ms"].get<double>(), 0.0) << name;
        }
        // Exact culling never draws fewer triangles than the visible set needs, nor more than all.
        const double oracle = s["oracle"]["triangles_p50"].get<double>();
        for (const char* name : {"frustum", "stop-and-wait", "chc", "chc++"}) {
          EXPECT_GE(s[name]["triangles_p50"].get<double>(), oracle) << trees << " " << path << " " << name;
          EXPECT_LE(s[name]["triangles_p50"].get<double>(), s["none"]["triangles_p50"].get<double>()) << name;
        }
        // The oracle's one-frame lag, written and printed (a share of its triangles).
        ASSERT_TRUE(run.contains("oracle_lag_triangles")) << trees << " " << path;
        EXPECT_GE(run["oracle_lag_triangles"].get<double>(), 0.0);
        EXPECT_EQ(s["none"]["queries_p50"].get<double>(), 0.0);
        EXPECT_GT(s["stop-and-wait"]["queries_p50"].get<double>(), 0.0);
        // The CPU's waits for query results: none without queries; a wait takes at least one
        // query's result, so no frame waits more often than it queries (and so neither do the
        // medians); stop-and-wait waits for its first query at the least.
        for (const char* name : {"none", "frustum"}) EXPECT_EQ(s[name]["waits_p50"].get<double>(), 0.0) << name;
        for (const char* name : {"stop-and-wait", "chc", "chc++"})
          EXPECT_LE(s[name]["waits_p50"].get<double>(), s[name]["queries_p50"].get<double>()) << trees << " " << path << " " << name;
        EXPECT_GE(s["stop-and-wait"]["waits_p50"].get<double>(), 1.0);
        // Every ratio is that strategy's p50 over frustum's and over the oracle's, as printed.
        const double frustumMs = s["frustum"]["p50_ms"].get<double>(), oracleMs = s["oracle"]["p50_ms"].get<double>();
        for (const char* name : {"none", "stop-and-wait", "chc", "chc++"}) {
          const double ms = s[name]["p50_ms"].get<double>();
          EXPECT_NEAR(s[name]["over_frustum"].get<double>(), ms / frustumMs, 1e-12 * ms / frustumMs) << name;
          EXPECT_NEAR(s[name]["over_oracle"].get<double>(), ms / oracleMs, 1e-12 * ms / oracleMs) << name;
        }
        for (const char* name : {"none", "frustum", "stop-and-wait", "chc", "chc++"}) {
          EXPECT_DOUBLE_EQ(s[name]["triangles_over_oracle"].get<double>(), s[name]["triangles_p50"].get<double>() / oracle) << name;
          // Brute force and frustum culling query nothing (the query-driven strategies ask the
          // terrain blocks with their triangles, [culling] terrain_blocks; chc++ its leaves too).
          if (std::string(name) == "none" || std::string(name) == "frustum") {
            EXPECT_EQ(s[name]["geometry_queries_p50"].get<double>(), 0.0) << name;
          }
          // The culler's own CPU time is part of each profiled frame (glFinish and a clock around
          // culling and drawing), so its median is no larger than the frame's.
          const double cpu = s[name]["culling_cpu_ms_p50"].get<double>();
          EXPECT_GT(cpu, 0.0) << name;
          if (std::string(timing) == "profile") {
            EXPECT_LE(cpu, s[name]["p50_ms"].get<double>()) << name;
          }
        }
        // The trees and props each strategy drew, sorted by the oracle's sets (bench_oracle.hpp).
        // Brute force draws all of them every frame: the four parts add up to the scene's trees
        // (forest.toml has no props), none is fresh (each hidden one was drawn the frame before),
        // and its visible and lag are the oracle's sets' sizes (|V_f|, |V_f-1 \ V_f|). Exact
        // culling draws every visible one, so all strategies have the oracle's `visible`.
        const auto& all = s["none"]["trees_and_props_drawn"];
        const auto& sets = s["oracle"]["trees_and_props_drawn"];
        EXPECT_DOUBLE_EQ(all["visible"].get<double>(), sets["visible"].get<double>()) << trees << " " << path;
        EXPECT_DOUBLE_EQ(all["lag"].get<double>(), sets["lag"].get<double>()) << trees << " " << path;
        const double sceneTrees = j["scenes"][trees]["trees"].get<double>();
        EXPECT_NEAR(all["visible"].get<double>() + all["lag"].get<double>() + all["carried"].get<double>(), sceneTrees, 1e-9 * sceneTrees)
            << trees << " " << path;
        EXPECT_EQ(all["fresh"].get<double>(), 0.0);
        for (const char* name : {"frustum", "stop-and-wait", "chc", "chc++"}) {
          const auto& d = s[name]["trees_and_props_drawn"];
          EXPECT_DOUBLE_EQ(d["visible"].get<double>(), all["visible"].get<double>()) << name;
          for (const char* part : {"lag", "carried", "fresh"}) EXPECT_GE(d[part].get<double>(), 0.0) << name << " " << part;
        }
        chcPlusPlusGeometryQueries += s["chc++"]["geometry_queries_p50"].get<double>();
      }
    }
  }
  EXPECT_GT(chcPlusPlusGeometryQueries, 0.0);  // on by default
  // chc++ as the paper has it (boxes only, tiles whole) draws from its render queue and queries in batches:
  // never more draw calls or state switches than chc (in these tiny scenes chc may need only a
  // couple as well). Geometry queries add a query stage of their own (its program is a switch).
  const fs::path boxesOnly = out / "boxes-only.toml";
  fs::create_directories(out);
  writeFileAtomic(boxesOnly, readTextFile(fs::path(FOREST_REPO_DATA) / "scenes" / "forest.toml") + "\n[culling]\ngeometry_queries = false\nterrain_blocks = false\n");
  const Result paper = runForest(fmt::format("bench culling --scene {} --trees 300,600 --paths ground,hill --frames 4 --width 160 "
                                             "--height 90 --strategies chc,chc++ --quiet --out {}", boxesOnly.string(), (out / "paper").string()));
  ASSERT_EQ(paper.exitCode, 0) << paper.err;
  const nlohmann::json p = nlohmann::json::parse(readTextFile(out / "paper" / "bench-culling.json"));
  for (const auto& [trees, paths] : p["runs"].items()) {
    for (const auto& [path, run] : paths.items()) {
      const auto& s = run["strategies"];
      EXPECT_EQ(s["chc++"]["geometry_queries_p50"].get<double>(), 0.0);
      EXPECT_LE(s["chc++"]["draw_calls_p50"].get<double>(), s["chc"]["draw_calls_p50"].get<double>()) << trees << " " << path;
      EXPECT_LE(s["chc++"]["state_switches_p50"].get<double>(), s["chc"]["state_switches_p50"].get<double>()) << trees << " " << path;
    }
  }
  const Result bad = runForest("bench culling --trees 0 --out " + (out / "bad").string());
  EXPECT_EQ(bad.exitCode, 2);
  EXPECT_THAT(bad.err, HasSubstr("--trees: Value 0 not in range 1 to 1000000"));
  EXPECT_FALSE(fs::exists(out / "bad"));
}

// --path: a camera path file instead of the built-in paths, sampled at --fps as forest walkthrough
// samples it. A still camera (two keys at one pose) sees the same set every frame: the oracle's
// one-frame lag is 0 exactly; 1 s at 4 frames per second is 5 frames.
TEST(ForestCli, BenchCullingRunsACameraPathFile) {
  const fs::path out = fs::path(FOREST_TEST_OUTPUT) / "cli" / "bench-culling-path";
  fs::remove_all(out);
  fs::create_directories(out);
  const fs::path still = out / "still.toml";
  writeFileAtomic(still, "heights = \"above_ground\"\n[[key]]\nt = 0.0\nposition = [0.0, 1.7, 0.0]\nyaw_deg = 30.0\n"
                         "[[key]]\nt = 1.0\nposition = [0.0, 1.7, 0.0]\nyaw_deg = 30.0\n");
  const Result r = runForest(fmt::format("bench culling --trees 300 --path {} --fps 4 --width 160 --height 90 --strategies frustum,chc++ "
                                         "--quiet --out {}", still.string(), (out / "run").string()));
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("still path ("));
  const nlohmann::json j = nlohmann::json::parse(readTextFile(out / "run" / "bench-culling.json"));
  EXPECT_EQ(j["frames_per_path"].get<int>(), 5);
  ASSERT_EQ(j["runs"].size(), 1u);
  const auto& runs = j["runs"].begin().value();
  ASSERT_EQ(runs.size(), 1u);
  ASSERT_TRUE(runs.contains("still"));
  EXPECT_EQ(runs["still"]["oracle_lag_triangles"].get<double>(), 0.0);
  // Nothing is visible in one frame and hidden in the next, and frustum culling draws the same
  // set every frame: no lag, and nothing it draws is fresh.
  for (const char* name : {"frustum", "chc++"})
    EXPECT_EQ(runs["still"]["strategies"][name]["trees_and_props_drawn"]["lag"].get<double>(), 0.0) << name;
  EXPECT_EQ(runs["still"]["strategies"]["frustum"]["trees_and_props_drawn"]["fresh"].get<double>(), 0.0);
  EXPECT_GT(runs["still"]["strategies"]["oracle"]["triangles_p50"].get<double>(), 0.0);

  const Result both = runForest(fmt::format("bench culling --path {} --paths ground --out {}", still.string(), (out / "both").string()));
  EXPECT_EQ(both.exitCode, 2);
  EXPECT_THAT(both.err, HasSubstr("--paths excludes --path"));
  const Result missing = runForest(fmt::format("bench culling --path {} --out {}", (out / "none.toml").string(), (out / "missing").string()));
  EXPECT_EQ(missing.exitCode, 2);
  EXPECT_THAT(missing.err, HasSubstr("none.toml"));
  // A grid scene (the thesis demo) takes square counts as its grid, on its own terrain.
  const std::string thesis = (fs::path(FOREST_REPO_DATA) / "scenes" / "thesis-demo.toml").string();
  const Result grid = runForest(fmt::format("bench culling --scene {} --trees 16 --path {} --fps 4 --width 160 --height 90 "
                                            "--strategies chc++ --quiet --out {}", thesis, still.string(), (out / "grid").string()));
  ASSERT_EQ(grid.exitCode, 0) << grid.err;
  const nlohmann::json g = nlohmann::json::parse(readTextFile(out / "grid" / "bench-culling.json"));
  ASSERT_TRUE(g["scenes"].contains("16")) << g["scenes"].dump();
  EXPECT_EQ(g["scenes"]["16"]["trees"].get<int>(), 16);
  EXPECT_DOUBLE_EQ(g["scenes"]["16"]["terrain_size_m"].get<double>(), 200.0);  // thesis-demo.toml's [terrain] size
  const Result notSquare = runForest(fmt::format("bench culling --scene {} --trees 17 --path {} --out {}", thesis, still.string(),
                                                 (out / "not-square").string()));
  EXPECT_EQ(notSquare.exitCode, 2);
  EXPECT_THAT(notSquare.err, HasSubstr("--trees 17: "));
  EXPECT_THAT(notSquare.err, HasSubstr("expected a square count"));
  const Result shortPath =
      runForest(fmt::format("bench culling --path {} --fps 4 --warmup 5 --out {}", still.string(), (out / "short").string()));
  EXPECT_EQ(shortPath.exitCode, 2);
  EXPECT_THAT(shortPath.err, HasSubstr("--warmup 5: expected fewer than the 5 frames of"));
}

// forest bench passes: every variant and floor measured, the ratios as the table prints them, the
// variants' images compared; a bad size refused.
TEST(ForestCli, BenchPassesTimesTheVariantsAgainstTheirFloors) {
  const fs::path out = fs::path(FOREST_TEST_OUTPUT) / "cli" / "bench-passes";
  fs::remove_all(out);
  const Result r = runForest(fmt::format("bench passes --views 2 --rounds 1 --sizes 320x180 --quiet --out {}", out.string()));
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(readTextFile(out / "passes.json"));
  ASSERT_EQ(j["sizes"].size(), 1u);
  const auto& size = j["sizes"][0];
  EXPECT_EQ(size["width"], 320);
  for (const char* variant : {"full", "half", "blur off"}) {
    const auto& v = size["variants"][variant];
    EXPECT_GT(v["lighting_ms_p50"].get<double>(), 0.0) << variant;
    EXPECT_NEAR(v["full_screen_ms_p50"].get<double>(),
                v["term_ms_p50"].get<double>() + v["blur_ms_p50"].get<double>() + v["lighting_ms_p50"].get<double>(),
                0.5 * v["full_screen_ms_p50"].get<double>())  // p50 of sums against the sum of p50s: 2 views
        << variant;
  }
  EXPECT_EQ(size["variants"]["full"]["mean_difference_255"], 0.0);  // the reference itself
  EXPECT_GT(size["variants"]["blur off"]["differing_share_max"].get<double>(), 0.0);  // no blur: edges differ
  EXPECT_EQ(size["variants"]["full"]["ssim_mean"], 1.0);
  EXPECT_LT(size["variants"]["blur off"]["ssim_min"].get<double>(), 1.0);  // SSIM < 1 where images differ
  for (const char* variant : {"half", "blur off"}) {
    EXPECT_LE(size["variants"][variant]["ssim_min"].get<double>(), size["variants"][variant]["ssim_mean"].get<double>()) << variant;
    EXPECT_LE(size["variants"][variant]["ssim_mean"].get<double>(), 1.0) << variant;
  }
  for (const auto& [name, ms] : size["floors_ms_p50"].items()) EXPECT_GT(ms.get<double>(), 0.0) << name;
  EXPECT_EQ(size["floors_ms_p50"].size(), 8u);
  const auto& ratios = size["ratios"];
  EXPECT_NEAR(ratios["half_over_full_full_screen"].get<double>(),
              size["variants"]["half"]["full_screen_ms_p50"].get<double>() / size["variants"]["full"]["full_screen_ms_p50"].get<double>(),
              1e-9);
  EXPECT_THAT(readTextFile(out / "passes.md"), HasSubstr("| half |"));
  const Result bad = runForest(fmt::format("bench passes --sizes 320by180 --out {}", (out / "bad").string()));
  EXPECT_EQ(bad.exitCode, 2);
  EXPECT_THAT(bad.err, HasSubstr("--sizes 320by180: expected WIDTHxHEIGHT"));
}

// bench scale on the landscape with few trees and frames: a run per path and count, every tree
// placed, the summary over the frames after the warm-up, and at each path's last view no caster
// the ray-traced truth needs left out (with the hidden crowns drawn the mask's selection holds them).
TEST(ForestCli, BenchScaleRunsEachPathWithEachTreeCount) {
  const fs::path out = fs::path(FOREST_TEST_OUTPUT) / "cli" / "bench-scale";
  fs::remove_all(out);
  // The crowns hidden from the sun drawn: the receiver mask's selection holds every caster the truth needs.
  const Result r = runForest(fmt::format("bench scale --trees 1000,4000 --fps 0.25 --width 320 --height 180 --hidden-casters draw --quiet --out {}",
                                         out.string()));
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(readTextFile(out / "scale.json"));
  ASSERT_EQ(j["runs"].size(), 4u);  // the landscape walk and flight, 1000 and 4000 trees each
  for (const auto& run : j["runs"]) {
    const std::string what = fmt::format("{} trees along {}", run["trees"].get<int>(), run["path"].get<std::string>());
    EXPECT_EQ(run["trees_placed"], run["trees"]) << what;
    const bool walk = run["path"].get<std::string>().find("landscape-walk") != std::string::npos;
    const int frames = walk ? 11 : 8;  // 40 s and 30 s at 0.25 frames a second, both ends
    EXPECT_EQ(run["summary"]["frames_measured"].get<int>(), frames - frames / 2) << what;
    EXPECT_GT(run["summary"]["interval_ms"]["p50"].get<double>(), 0.0) << what;
    EXPECT_GT(run["startup"]["total_ms"].get<double>(), 0.0) << what;
    EXPECT_EQ(run["truth"]["casters_missing"].get<int>(), 0) << what;
    EXPECT_GE(run["truth"]["casters_selected"].get<int>(), run["truth"]["casters_needed"].get<int>()) << what;
  }
  EXPECT_THAT(readTextFile(out / "scale.md"), HasSubstr("| landscape-flight | 4000 |"));
  EXPECT_TRUE(fs::exists(out / "scale.png"));
  EXPECT_EQ(runForest(fmt::format("bench scale --trees 0 --out {}", (out / "bad").string())).exitCode, 2);
  const Result tooMany = runForest(fmt::format("bench scale --scene {}/scenes/forest.toml --trees 6000 --out {}", FOREST_REPO_DATA, (out / "bad").string()));
  EXPECT_EQ(tooMany.exitCode, 2);
  EXPECT_THAT(tooMany.err, HasSubstr("--trees 6000: at most the scene's count, 5000"));
}

// Layouts at equal total texels (bench speed-error --far-slice-scale): K − 1 layers of side s and
// one of r · s with (K − 1 + r²) · s² = N², each side rounded; layers under 512² left out.
TEST(ForestCli, SpeedErrorLayoutsKeepTheTotalTexels) {
  for (double r : {0.5, 0.75, 1.0, 1.5, 2.0})
    for (const app::MapLayout& layout : app::mapLayouts({1024, 2048, 4096}, {1, 2, 4}, r)) {
      const double expectedSide = layout.totalSide / std::sqrt(layout.cascades == 1 ? 1.0 : layout.cascades - 1 + r * r);
      EXPECT_LE(std::abs(layout.layerSize - expectedSide), 0.5) << layout.label();
      EXPECT_EQ(layout.farSize(), layout.cascades == 1 ? layout.layerSize : static_cast<int>(std::lround(r * layout.layerSize)));
      // Sides rounded: s by up to δ = 1/2, the far side round(r · s) by up to δ_f = (1 + r) / 2 from r
      // times the exact s; a side a off by δ moves a² by at most 2aδ + δ².
      const int k = layout.cascades;
      const double far = k == 1 ? expectedSide : r * expectedSide, farDelta = k == 1 ? 0.5 : 0.5 * (1.0 + r);
      const double bound = (k - 1) * (2.0 * expectedSide * 0.5 + 0.25) + 2.0 * far * farDelta + farDelta * farDelta;
      EXPECT_LE(std::abs(static_cast<double>(layout.texels()) - static_cast<double>(layout.totalSide) * layout.totalSide), bound)
          << layout.label();
      EXPECT_GE(layout.layerSize, 512);
    }
  EXPECT_EQ(app::mapLayouts({2048}, {4}, 1.5).front().label(), "3×894²+1341²");
  EXPECT_EQ(app::mapLayouts({2048}, {4}, 1.0).front().label(), "4×1024²");
  EXPECT_EQ(app::mapLayouts({2048}, {2}, 0.5).front().label(), "1832²+916²");
  EXPECT_TRUE(app::mapLayouts({1024}, {4}, 2.0).empty());  // 1024 / √7 = 387 < 512
}

}  // namespace
}  // namespace forest
