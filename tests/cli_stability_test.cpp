// forest stability on the command line: its records hold under a check that uses none of the
// engine's geometry code, it reports aliasing per method, and bad case files are named.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "cli_test_support.hpp"
#include "test_paths.hpp"

namespace forest {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using test::runForest;

// Checks the records of `forest stability --out` without the engine's geometry code: points
// sampled in the camera frustum ∩ S (from the case's own fields) must land inside the map with
// the record's float32 camera-relative matrix.
TEST(ForestCli, StabilityRecordsHoldUnderAnIndependentCheck) {
  const fs::path records = fs::path(FOREST_TEST_OUTPUT) / "cli" / "stability.jsonl";
  fs::remove(records);
  const test::CliResult r = runForest("stability --cases " + std::string(FOREST_REPO_DATA) + "/stability/hard-cases.json" +
                             " --random 300 --seed 5 --out " + records.string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("0 failed"));
  std::ifstream in(records);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int count = 0, sampled = 0;
  for (std::string line; std::getline(in, line);) {
    ++count;
    const nlohmann::json j = nlohmann::json::parse(line);
    if (j.contains("refused")) {  // a view outside the float32 domain: the reason names the limit
      EXPECT_THAT(j.at("refused").get<std::string>(), HasSubstr("2^-23")) << line;
      continue;
    }
    ASSERT_TRUE(j.at("passed").get<bool>()) << line;
    const auto m = j.at("eye_relative_to_shadow_clip").get<std::vector<double>>();
    ASSERT_EQ(m.size(), 16u);
    for (double v : m) ASSERT_TRUE(std::isfinite(v));
    ASSERT_EQ(j.at("world_to_shadow_clip").size(), 16u);
    if (j.at("empty").get<bool>()) continue;
    const nlohmann::json& c = j.at("input");
    auto v3 = [&](const char* key) {
      const auto a = c.at(key).get<std::vector<double>>();
      return glm::dvec3(a[0], a[1], a[2]);
    };
    const glm::dvec3 eye = v3("eye"), f = glm::normalize(v3("view_dir"));
    const glm::dvec3 right = glm::normalize(glm::cross(f, v3("up"))), up = glm::cross(right, f);
    const double tanHalf = std::tan(glm::radians(c.at("fovy_deg").get<double>()) / 2.0);
    const double aspect = c.at("aspect").get<double>(), near = c.at("near").get<double>(), far = c.at("far").get<double>();
    const glm::dvec3 sMin = v3("scene_min"), sMax = v3("scene_max");
    for (int k = 0; k < 200; ++k) {
      const double t = near * std::pow(far / near, unit(rng));
      const glm::dvec3 p = eye + t * (f + (2 * unit(rng) - 1) * tanHalf * aspect * right + (2 * unit(rng) - 1) * tanHalf * up);
      if (glm::any(glm::lessThan(p, sMin)) || glm::any(glm::greaterThan(p, sMax))) continue;
      if (c.contains("receivers")) {
        const auto& box = c.at("receivers")[0];
        const auto lo = box.at("min").get<std::vector<double>>(), hi = box.at("max").get<std::vector<double>>();
        if (p.x < lo[0] || p.y < lo[1] || p.z < lo[2] || p.x > hi[0] || p.y > hi[1] || p.z > hi[2]) continue;
      }
      const glm::dvec3 q = p - eye;
      double h[4];
      for (int row = 0; row < 4; ++row) h[row] = m[row] * q.x + m[4 + row] * q.y + m[8 + row] * q.z + m[12 + row];
      ASSERT_GT(h[3], 0.0) << j.at("case");
      EXPECT_LE(std::abs(h[0] / h[3]), 1.0 + 1e-5) << j.at("case") << " " << j.at("method");
      EXPECT_LE(std::abs(h[1] / h[3]), 1.0 + 1e-5) << j.at("case") << " " << j.at("method");
      // Depth: clip z / w, or for tsm the linear light-depth row (TSM §4).
      double depth = h[2] / h[3];
      if (j.contains("eye_relative_to_light_depth")) {
        const auto row = j.at("eye_relative_to_light_depth").get<std::vector<double>>();
        depth = row[0] * q.x + row[1] * q.y + row[2] * q.z + row[3];
      }
      EXPECT_LE(std::abs(depth), 1.0 + 1e-5) << j.at("case") << " " << j.at("method");
      ++sampled;
    }
  }
  EXPECT_EQ(count, 5 * (30 + 300));  // uniform, uniform-stable, lispsm, tsm, tsm-iterative; 30 hard cases
  EXPECT_GT(sampled, 10000);
}

TEST(ForestCli, StabilityReportsAliasingPerMethod) {
  const test::CliResult r = runForest("stability --cases " + std::string(FOREST_REPO_DATA) + "/stability/hard-cases.json --aliasing --json");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  const nlohmann::json& medians = j.at("aliasing_medians");
  for (const char* method : {"uniform", "uniform-stable", "lispsm", "tsm", "tsm-iterative"}) {
    EXPECT_GT(medians.at(method).at("cases").get<int>(), 20) << method;
    EXPECT_GE(medians.at(method).at("perspective_max_over_floor").get<double>(), 1.0) << method;  // nothing beats eq. 8.4
  }
  // The warped maps beat the uniform one on the hard cases' median.
  EXPECT_LT(medians.at("lispsm").at("perspective_max_relative").get<double>(),
            medians.at("uniform").at("perspective_max_relative").get<double>());
  EXPECT_LT(medians.at("tsm").at("storage_factor").get<double>(), medians.at("uniform").at("storage_factor").get<double>());
}

TEST(ForestCli, StabilityRejectsBadCaseFiles) {
  const std::string file = test::badInput("stability-near-far.json");
  test::expectOneLineError(runForest("stability --cases " + file), file + ": case 2 ('far before near'): far",
                     "expected far > near (10), got 5");
  const test::CliResult none = runForest("stability");
  EXPECT_EQ(none.exitCode, 2);
  EXPECT_THAT(none.err, HasSubstr("give --cases FILE and/or --random N"));
}

}  // namespace
}  // namespace forest
