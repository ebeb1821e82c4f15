// forest bench speed-error --quick: the documented report, rows at equal total texels (one map and
// four layers), bands that add up, plots with ink, the worst-case images.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>

#include <nlohmann/json.hpp>

#include "cli_test_support.hpp"
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
  for (const char* key : {"version", "scene", "device", "timing", "queries", "resolution", "quick", "map_sizes", "soft_rays",
                          "target_misclassification", "scenarios", "rows", "flicker", "equal_error_map_size"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_EQ(j["timing"], "profile");  // auto on llvmpipe
  // 2 scenarios × 4 methods × (2 focus bounds at 1024², receivers at 4 × 512²) × blur on / off.
  ASSERT_EQ(j["rows"].size(), 48u);
  int cascaded = 0;
  for (const auto& row : j["rows"]) {
    for (const char* key : {"scenario", "method", "focus", "cascades", "map_size", "total_texels", "blur", "frame_ms", "shadow_ms",
                            "shadow_triangles", "misclassification", "near_edge", "elsewhere", "false_shadow", "false_light", "bands",
                            "soft_mae", "aliasing_p95_px", "aliasing_max_px", "lit_facing_pixels", "casters_selected", "casters_needed",
                            "casters_missing"})
      ASSERT_TRUE(row.contains(key)) << key;
    // Equal total texels: one 1024² map or four 512² layers.
    EXPECT_EQ(row["total_texels"].get<long long>(), 1024LL * 1024);
    EXPECT_EQ(row["map_size"].get<int>(), row["cascades"].get<int>() == 4 ? 512 : 1024);
    cascaded += row["cascades"].get<int>() == 4 ? 1 : 0;
    ASSERT_EQ(row["bands"].size(), 3u);
    int bandPixels = 0;
    for (const auto& band : row["bands"]) bandPixels += band["lit_facing"].get<int>();
    EXPECT_EQ(bandPixels, row["lit_facing_pixels"].get<int>());
    EXPECT_GT(row["frame_ms"].get<double>(), row["shadow_ms"].get<double>());
    EXPECT_GE(row["misclassification"].get<double>(), 0.0);
    EXPECT_LE(row["misclassification"].get<double>(), 1.0);
    EXPECT_NEAR(row["misclassification"].get<double>(), row["false_shadow"].get<double>() + row["false_light"].get<double>(), 1e-12);
    EXPECT_EQ(row["casters_missing"].get<int>(), 0) << row["scenario"] << " " << row["method"];
  }
  EXPECT_EQ(cascaded, 16);
  EXPECT_EQ(j["flicker"].size(), 12u);
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

}  // namespace
}  // namespace forest
