// What the main walk and the stress runs promise beside their numbers: a camera that never enters a
// tree, and a run that says when it is too short for what it reports.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>

#include "cli_test_support.hpp"
#include "forest/core/files.hpp"
#include "test_paths.hpp"

namespace forest {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::Not;
using Result = test::CliResult;
using test::runForest;

// The main walk keeps its camera clear of every trunk, crown and prop in every frame (the eye
// outside them, nothing between it and the near plane: raytrace::cameraClearance, checked against
// the trees at the LOD and sway the renderer gives them), because the scene's trail keeps the trees
// off its route; in the same forest without the trail the walk passes through conifers and
// shrubs, and the check names those frames.
TEST(ForestCli, TheMainWalkStaysClearOfTrunksAndCrowns) {
  const std::string walk = " --clearance --path " + std::string(FOREST_REPO_DATA) + "/paths/walk.toml";
  const std::string forest = std::string(FOREST_REPO_DATA) + "/scenes/forest.toml";
  const Result clear = runForest("check --scene " + forest + walk);
  EXPECT_EQ(clear.exitCode, 0) << clear.out << clear.err;
  EXPECT_THAT(clear.out, HasSubstr("clearance: 1201 of 1201 frames clear"));
  std::string withoutTrail = readTextFile(forest);
  withoutTrail.erase(withoutTrail.find("[vegetation.trail]"));  // the last table of the file
  const fs::path noTrail = fs::path(FOREST_TEST_OUTPUT) / "cli" / "forest-without-trail.toml";
  writeFileAtomic(noTrail, withoutTrail);
  const Result old = runForest("check --scene " + noTrail.string() + walk);
  EXPECT_EQ(old.exitCode, 1) << old.out << old.err;
  EXPECT_THAT(old.out, HasSubstr("the eye is inside: tree "));
  EXPECT_THAT(old.out, HasSubstr("it cuts the near plane: tree "));
}

// A run too short for what stress reports says so and leaves those numbers out: 20 frames (the
// default warm-up then at most half: 10) measure 10, fewer than the 100 a memory slope needs, and
// the exactness check every 50th frame checks none.
TEST(ForestCli, StressSaysWhenARunIsTooShortForItsSlopesAndChecks) {
  const fs::path folder = fs::path(FOREST_TEST_OUTPUT) / "cli" / "stress-short";
  fs::remove_all(folder);
  const Result r = runForest("stress --scene " + std::string(FOREST_REPO_DATA) + "/scenes/park.toml --trees 200 --frames 20 "
                             "--check-every 50 --width 64 --height 36 --quiet --out " + folder.string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_THAT(r.err, HasSubstr("stress: warning: 20 frames per run (10 warm-up): 10 measured frames are too few for the memory "
                               "slopes (they need 100; left out), no frame is checked for exactness"));
  const nlohmann::json j = nlohmann::json::parse(readTextFile(folder / "stress.json"));
  EXPECT_EQ(j["warmup"].get<int>(), 10);
  const nlohmann::json& run = j["runs"][0];
  EXPECT_TRUE(run["rss_mib"]["slope_percent_per_100_frames"].is_null());
  EXPECT_TRUE(run["heap_in_use_mib"]["slope_percent_per_100_frames"].is_null());
  EXPECT_EQ(run["exactness"]["checked_frames"].get<int>(), 0);
  EXPECT_THAT(r.out, HasSubstr("not checked"));
  EXPECT_THAT(r.out, Not(HasSubstr("exact, ")));  // the checked cell reads "exact, N fr"
  EXPECT_THAT(readTextFile(folder / "stress.md"), HasSubstr("Too short: "));
}

}  // namespace
}  // namespace forest
