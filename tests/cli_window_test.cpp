// The window mode (forest walkthrough --window) driven by input scripts: every key switches its
// setting on the frame it is pressed, the recorded path replays headless, bad scripts are named
// before a window opens. Runs under xvfb-run (ctest's cli_window entry).
#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "cli_test_support.hpp"
#include "forest/core/camera_path.hpp"
#include "forest/core/files.hpp"
#include "forest/core/image.hpp"
#include "test_paths.hpp"

namespace forest {
namespace {
namespace fs = std::filesystem;
using ::testing::HasSubstr;
using Result = test::CliResult;
using test::expectOneLineError;
using test::runForest;

// Settings and camera of each frame of a window run's report.
nlohmann::json windowReport(const fs::path& out) { return nlohmann::json::parse(readTextFile(out / "report.json"))["frames"]; }

TEST(ForestWindow, ScriptedKeysSwitchEverySettingAndTheRecordedPathReplays) {
  const fs::path base = fs::path(FOREST_TEST_OUTPUT) / "cli" / "window";
  fs::remove_all(base);
  fs::create_directories(base);
  // At 30 fps frame k is at t = k/30: each key is tapped at frame 3k (t = 0.1·k) and acts from that frame on.
  const std::string script = R"(
[[event]]
t = 0.0
key = "w"
action = "press"
[[event]]
t = 0.1
key = "f"
[[event]]
t = 0.2
look = [600, 0]
[[event]]
t = 0.3
key = "f"
[[event]]
t = 0.4
key = "c"
[[event]]
t = 0.5
key = "m"
[[event]]
t = 0.6
key = "["
[[event]]
t = 0.7
key = "b"
[[event]]
t = 0.8
key = "left"
[[event]]
t = 0.9
key = "up"
[[event]]
t = 1.0
key = "w"
action = "release"
[[event]]
t = 1.0
key = "h"
)";
  writeFileAtomic(base / "script.toml", script);
  const fs::path out = base / "run", record = base / "flown.toml";
  const Result r = runForest("walkthrough --window --script " + (base / "script.toml").string() + " --record " + record.string() +
                             " --width 320 --height 180 --out " + out.string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const nlohmann::json frames = windowReport(out);
  ASSERT_EQ(frames.size(), 31u);  // frames 0 … 30; the last event is at frame 30
  // Without --path the window starts where the headless walkthrough does, at the main walk's start
  // (frame 0 has not moved yet: no time has passed).
  const CameraPath walk = CameraPath::load(std::string(FOREST_REPO_DATA) + "/paths/walk.toml");
  const CameraPose start = walk.at(walk.startTime());
  EXPECT_NEAR(frames[0]["eye"][0].get<double>(), start.position.x, 1e-9);
  EXPECT_NEAR(frames[0]["eye"][2].get<double>(), start.position.z, 1e-9);
  auto at = [&](int k) { return frames[static_cast<size_t>(k)]; };
  auto setting = [&](int k, const char* name) { return at(k)["settings"][name]; };

  // Freeze (frames 3–8): the visible set stays while the camera moves and turns 90°; it changes after.
  EXPECT_FALSE(setting(2, "frozen").get<bool>());
  for (int k = 3; k < 9; ++k) {
    EXPECT_TRUE(setting(k, "frozen").get<bool>()) << k;
    EXPECT_EQ(at(k)["visible_set_hash"], at(3)["visible_set_hash"]) << k;
    EXPECT_THAT(at(k)["stats_line"].get<std::string>(), HasSubstr("CULLING FROZEN"));
  }
  EXPECT_NE(at(6)["eye"], at(3)["eye"]);
  EXPECT_NEAR(at(6)["yaw_deg"].get<double>(), at(5)["yaw_deg"].get<double>() - 90.0, 1e-9);  // 600 px × 0.15°
  EXPECT_NE(at(9)["visible_set_hash"], at(3)["visible_set_hash"]);
  EXPECT_THAT(at(9)["stats_line"].get<std::string>(), ::testing::Not(HasSubstr("FROZEN")));

  // Each key changes its setting from its frame on, and the stats line shows the new value.
  struct Switch {
    int frame;
    const char* name;
  };
  for (const Switch& sw : {Switch{12, "culling"}, Switch{15, "method"}, Switch{18, "shadow_size"}, Switch{21, "blur_px"},
                           Switch{24, "sun_azimuth_deg"}, Switch{27, "sun_elevation_deg"}}) {
    EXPECT_EQ(setting(sw.frame - 1, sw.name), setting(0, sw.name)) << sw.name;
    EXPECT_NE(setting(sw.frame, sw.name), setting(sw.frame - 1, sw.name)) << sw.name;
  }
  EXPECT_EQ(setting(12, "culling"), "none");  // chc++ (the default) → none: the cycle wraps
  EXPECT_THAT(at(12)["stats_line"].get<std::string>(), HasSubstr("| none |"));
  EXPECT_EQ(setting(15, "method"), "tsm");  // lispsm → tsm
  EXPECT_THAT(at(15)["stats_line"].get<std::string>(), HasSubstr("| tsm 2048 |"));
  EXPECT_EQ(setting(18, "shadow_size").get<int>(), 1024);
  EXPECT_THAT(at(18)["stats_line"].get<std::string>(), HasSubstr("| tsm 1024 |"));
  EXPECT_EQ(setting(21, "blur_px").get<double>(), 6.0);  // 3 → 6
  EXPECT_THAT(at(21)["stats_line"].get<std::string>(), HasSubstr("| blur 6 |"));
  EXPECT_NEAR(setting(24, "sun_azimuth_deg").get<double>(), setting(23, "sun_azimuth_deg").get<double>() - 10.0, 1e-9);
  EXPECT_NEAR(setting(27, "sun_elevation_deg").get<double>(), setting(26, "sun_elevation_deg").get<double>() + 5.0, 1e-9);
  EXPECT_TRUE(setting(29, "help").get<bool>());
  EXPECT_FALSE(setting(30, "help").get<bool>());
  for (const auto& f : frames) {
    const std::string line = f["stats_line"];
    EXPECT_THAT(line, HasSubstr(fmt::format("visible {} |", f["visible_objects"].get<int>())));
    EXPECT_THAT(line, HasSubstr(fmt::format("casters {} |", f["casters"].get<int>())));
  }

  // The window image has the stats line: a dark band at the bottom with white text in it.
  const Image8 shown = readImage8(out / "window.png");
  ASSERT_EQ(shown.width, 320);
  int white = 0;
  for (int y = shown.height - 16; y < shown.height; ++y)
    for (int x = 0; x < shown.width; ++x)
      if (shown.at(x, y, 0) > 230 && shown.at(x, y, 1) > 230 && shown.at(x, y, 2) > 230) ++white;
  EXPECT_GT(white, 100);

  // The recorded path replays headless to the same camera positions.
  const fs::path replay = base / "replay";
  const Result again = runForest("walkthrough --path " + record.string() + " --width 320 --height 180 --every 1000 --quiet --out " +
                                 replay.string());
  ASSERT_EQ(again.exitCode, 0) << again.err;
  const nlohmann::json replayed = nlohmann::json::parse(readTextFile(replay / "report.json"))["frames"];
  ASSERT_EQ(replayed.size(), frames.size());
  for (size_t k = 0; k < frames.size(); ++k)
    for (int i = 0; i < 3; ++i)
      EXPECT_NEAR(replayed[k]["eye"][i].get<double>(), frames[k]["eye"][i].get<double>(), 1e-6) << "frame " << k;
}

TEST(ForestWindow, BadScriptsAreNamedBeforeAWindowOpens) {
  const fs::path base = fs::path(FOREST_TEST_OUTPUT) / "cli" / "window-bad";
  fs::remove_all(base);
  fs::create_directories(base);
  writeFileAtomic(base / "script.toml", "[[event]]\nt = 0.5\nkey = \"x\"\n");
  const Result key = runForest("walkthrough --window --script " + (base / "script.toml").string() + " --out " + (base / "out").string());
  expectOneLineError(key, (base / "script.toml").string(), "event[0].key = 'x': expected one of");
  const Result missing = runForest("walkthrough --window --script " + (base / "none.toml").string() + " --out " + (base / "out").string());
  EXPECT_EQ(missing.exitCode, 2);
  EXPECT_THAT(missing.err, HasSubstr("none.toml"));
  const Result backend = runForest("walkthrough --window --gl osmesa --out " + (base / "out").string());
  EXPECT_EQ(backend.exitCode, 2);
  EXPECT_THAT(backend.err, HasSubstr("--gl osmesa with --window"));
  const Result record = runForest("walkthrough --record x.toml --out " + (base / "out").string());  // needs --window
  EXPECT_NE(record.exitCode, 0);
  EXPECT_THAT(record.err, HasSubstr("--window"));
  EXPECT_FALSE(fs::exists(base / "out")) << "no partial output";
}

}  // namespace
}  // namespace forest
