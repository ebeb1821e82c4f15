// What a multi-frame command leaves in its output folder (apps/forest/run_output.hpp): a contact
// sheet that spans the whole run, labelled; a folder that holds one run only; the walk's video.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <tuple>

#include "cli_test_support.hpp"
#include "forest/core/image.hpp"
#include "run_output.hpp"
#include "test_paths.hpp"

namespace forest {
namespace {

namespace fs = std::filesystem;

Image8 greyFrame(int width, int height) {
  Image8 image(width, height, 4);
  std::fill(image.pixels.begin(), image.pixels.end(), static_cast<unsigned char>(100));
  return image;
}

// Feeds a run of `frames` frames the way the walkthrough does (the frames the sheet wants, then the
// last one done) and returns the frames the sheet shows.
std::vector<int> shownForRun(int frames) {
  app::ContactSheet sheet;
  const Image8 image = greyFrame(32, 18);
  for (int f = 0; f < frames; ++f)
    if (sheet.wants(f)) sheet.add(f, f / 30.0, 10.0, image);
  if (!sheet.has(frames - 1)) sheet.add(frames - 1, (frames - 1) / 30.0, 10.0, image);
  return sheet.shownFrames();
}

TEST(RunOutput, ContactSheetSpansTheWholeRunFromFirstToLastFrame) {
  // Runs of any length, including an interrupted one (54 frames) and the main job (901): the sheet
  // shows min(16, frames) frames, the first and the last among them, in order, with no gap wider
  // than twice the even spacing (frames − 1) / 15 plus one frame (the sampling keeps every k-th frame,
  // k a power of two, so spacing can only double).
  for (int frames : {1, 2, 5, 16, 17, 20, 33, 54, 100, 901, 5000}) {
    const std::vector<int> shown = shownForRun(frames);
    ASSERT_EQ(shown.size(), static_cast<size_t>(std::min(16, frames))) << frames;
    EXPECT_EQ(shown.front(), 0) << frames;
    EXPECT_EQ(shown.back(), frames - 1) << frames;
    const double evenSpacing = (frames - 1) / 15.0;
    for (size_t i = 1; i < shown.size(); ++i) {
      EXPECT_GT(shown[i], shown[i - 1]) << frames;
      EXPECT_LE(shown[i] - shown[i - 1], 2.0 * evenSpacing + 1.0) << frames << ": " << shown[i - 1] << " → " << shown[i];
    }
  }
}

TEST(RunOutput, ContactSheetLabelsEveryThumbnail) {
  app::ContactSheet sheet;
  for (int f = 0; f < 6; ++f) sheet.add(f, f / 30.0, 40.0 + f, greyFrame(200, 100));
  const Image8 composed = sheet.compose();
  // Four 200-px thumbnails per row, 2 px apart; two rows for six frames.
  ASSERT_EQ(composed.width, 4 * 200 + 3 * 2);
  ASSERT_EQ(composed.height, 2 * 100 + 2);
  // Each thumbnail's label: a darkened band at its bottom with light text on it (the frame itself
  // is uniform grey 100, so light pixels there can only be the label).
  for (int i = 0; i < 6; ++i) {
    const int x0 = (i % 4) * 202, y0 = (i / 4) * 102;
    int light = 0, dark = 0;
    for (int y = y0 + 100 - 18; y < y0 + 100; ++y)
      for (int x = x0; x < x0 + 200; ++x) {
        light += composed.at(x, y, 0) > 180 ? 1 : 0;
        dark += composed.at(x, y, 0) < 60 ? 1 : 0;
      }
    EXPECT_GT(light, 30) << "thumbnail " << i << " has no label text";
    EXPECT_GT(dark, 1000) << "thumbnail " << i << " has no label band";
  }
}

TEST(RunOutput, AnEarlierRunsFilesAreRemovedAndNothingElse) {
  const fs::path folder = fs::path(FOREST_TEST_OUTPUT) / "run-output";
  fs::remove_all(folder);
  fs::create_directories(folder / "frames");
  for (const fs::path& file : {folder / "report.json", folder / "contact-sheet.png", folder / "window.png", folder / "frames" / "frame00900.png",
                               folder / "frames" / "frame00020.png", folder / "notes.txt", folder / "frames" / "keep.txt"})
    std::ofstream(file) << "x";
  EXPECT_EQ(app::clearEarlierWalk(folder), 5);
  EXPECT_FALSE(fs::exists(folder / "frames" / "frame00900.png"));
  EXPECT_FALSE(fs::exists(folder / "report.json"));
  EXPECT_TRUE(fs::exists(folder / "notes.txt"));
  EXPECT_TRUE(fs::exists(folder / "frames" / "keep.txt"));
  EXPECT_EQ(app::clearEarlierWalk(folder / "absent"), 0);  // a new folder: nothing to do
}

// What ffprobe says of a video's first stream: "width,height,frames" (frames decoded and counted).
std::string probeVideo(const fs::path& video) {
  const std::string command = "ffprobe -v error -count_frames -select_streams v:0 -show_entries "
                              "stream=width,height,nb_read_frames -of csv=p=0 '" + video.string() + "' 2>&1";
  std::string out;
  if (FILE* pipe = popen(command.c_str(), "r")) {
    char buffer[256];
    while (fgets(buffer, sizeof buffer, pipe) != nullptr) out += buffer;
    pclose(pipe);
  }
  while (!out.empty() && (out.back() == '\n' || out.back() == ',')) out.pop_back();
  return out;
}

// A walk writes walkthrough.mp4 by default (ffmpeg, installed by tools/setup.sh): one video frame
// per rendered frame, not per PNG written (every 10th), at the frame's size — an odd one padded to
// the next even size (yuv420p). --no-video writes none.
TEST(RunOutput, WalkWritesAVideoOfEveryFrameByDefault) {
  ASSERT_EQ(std::system("command -v ffmpeg > /dev/null && command -v ffprobe > /dev/null"), 0)
      << "ffmpeg and ffprobe are missing: tools/setup.sh installs them";
  for (const auto& [width, height, expected] : {std::tuple{160, 90, "160,90,12"}, std::tuple{161, 91, "162,92,12"}}) {
    const fs::path out = fs::path(FOREST_TEST_OUTPUT) / "cli" / ("video-" + std::to_string(width));
    fs::remove_all(out);
    const test::CliResult r = test::runForest("walkthrough --frames 12 --warmup 2 --width " + std::to_string(width) +
                                              " --height " + std::to_string(height) + " --quiet --out " + out.string());
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_THAT(r.out, ::testing::HasSubstr("walkthrough.mp4 of all 12 frames"));
    EXPECT_EQ(probeVideo(out / "walkthrough.mp4"), expected);
    int pngs = 0;
    for (const auto& entry : fs::directory_iterator(out / "frames")) pngs += entry.path().extension() == ".png";
    EXPECT_EQ(pngs, 3);  // frames 0, 10 and the last
  }
  const fs::path out = fs::path(FOREST_TEST_OUTPUT) / "cli" / "video-none";
  fs::remove_all(out);
  const test::CliResult r = test::runForest("walkthrough --frames 4 --width 160 --height 90 --no-video --quiet --out " + out.string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_FALSE(fs::exists(out / "walkthrough.mp4"));
  EXPECT_THAT(r.out, ::testing::Not(::testing::HasSubstr("mp4")));
}

// An --out that cannot be written is a usage error (exit 2, one line naming --out and why) before
// any work: the scene given with it is a bad file, and the error is still the --out one. The
// check leaves nothing behind.
void expectOutputError(const std::string& arguments, const std::string& why, bool withScene = true) {
  SCOPED_TRACE("forest " + arguments);
  const std::string badScene = std::string(FOREST_TEST_DATA) + "/bad/terrain-octaves.toml";
  const test::CliResult r = test::runForest(arguments + (withScene ? " --scene " + badScene : std::string()));
  EXPECT_EQ(r.exitCode, 2) << r.err;
  EXPECT_THAT(r.err, ::testing::StartsWith("forest: error: "));
  EXPECT_THAT(r.err, ::testing::HasSubstr("--out"));
  EXPECT_THAT(r.err, ::testing::HasSubstr(why));
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

TEST(RunOutput, OutputPathMistakesAreUsageErrorsBeforeAnyWork) {
  const fs::path base = fs::path(FOREST_TEST_OUTPUT) / "cli" / "out-mistakes";
  fs::remove_all(base);
  fs::create_directories(base / "folder.png");
  const fs::path file = base / "file.txt";
  std::ofstream(file) << "x";
  // A folder-writing command given a file, a path under a file, a folder it cannot create.
  const std::string budget = "budget --budget " + std::string(FOREST_REPO_DATA) + "/budgets/llvmpipe-2core.toml";
  for (const std::string& command : {std::string("walkthrough"), budget, std::string("stress"), std::string("bench culling"),
                                    std::string("bench speed-error")}) {
    expectOutputError(command + " --out " + file.string(), "a file is there, expected a folder");
    expectOutputError(command + " --out " + (file / "sub").string(), "is a file, not a folder");
  }
  expectOutputError("walkthrough --out /sys/forest-test-out", "cannot create the folder");
  // A file-writing command given a folder, a missing folder (not created for it), an unwritable one.
  expectOutputError("render --out " + (base / "folder.png").string(), "a folder is there, expected a file");
  expectOutputError("render --out " + (base / "missing" / "x.png").string(), "does not exist");
  EXPECT_FALSE(fs::exists(base / "missing"));
  expectOutputError("render --out /sys/forest-test.png", "cannot create a file in it");
  expectOutputError("stability --out " + (base / "folder.png").string(), "a folder is there, expected a file", false);
  // The check creates nothing: a new, writable folder with a bad scene is left absent.
  const test::CliResult r = test::runForest("walkthrough --out " + (base / "new" / "deeper").string() + " --scene " +
                                            std::string(FOREST_TEST_DATA) + "/bad/terrain-octaves.toml");
  EXPECT_EQ(r.exitCode, 2) << r.err;
  EXPECT_THAT(r.err, ::testing::HasSubstr("terrain.octaves"));
  EXPECT_FALSE(fs::exists(base / "new"));
}

}  // namespace
}  // namespace forest
