#pragma once
// The forest command line as a test runs it: the program in a child process, its exit code and
// output; the one-line error format every usage and input error follows.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <glm/glm.hpp>

#include <cmath>

#include "forest/core/files.hpp"
#include "forest/core/image.hpp"
#include "test_paths.hpp"

namespace forest::test {

struct CliResult {
  int exitCode = -1;
  std::string out;
  std::string err;
};

// `environment`: assignments put before the program on its command line ("NAME=value …"), if any.
inline CliResult runForest(const std::string& arguments, const std::string& environment = "") {
  namespace fs = std::filesystem;
  const fs::path folder = fs::path(FOREST_TEST_OUTPUT) / "cli";
  fs::create_directories(folder);
  // Per process: cli_tests and cli_window (this program under xvfb-run) may run at the same time.
  const std::string pid = std::to_string(getpid());
  const fs::path out = folder / ("stdout-" + pid + ".txt"), err = folder / ("stderr-" + pid + ".txt");
  const std::string command =
      (environment.empty() ? std::string() : environment + " ") + std::string(FOREST_EXE) + " " + arguments + " > " + out.string() + " 2> " + err.string() + " < /dev/null";
  const int status = std::system(command.c_str());
  CliResult r;
  r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = readTextFile(out);
  r.err = readTextFile(err);
  return r;
}

// One line "forest: error: FILE…KEY…", exit code 2.
// A file of tests/data/bad (the inputs each command must refuse with one clear line).
inline std::string badInput(const std::string& name) { return std::string(FOREST_TEST_DATA) + "/bad/" + name; }

inline void expectOneLineError(const CliResult& r, const std::string& file, const std::string& key) {
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_THAT(r.err, ::testing::StartsWith("forest: error: " + file));
  EXPECT_THAT(r.err, ::testing::HasSubstr(key));
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

// The sky's colour at a pixel lies between the zenith's (the scene's sky_color) and the horizon's,
// mix(zenith, (0.75, 0.8, 0.85), 0.55) in linear light (shaders/lighting.frag), channel by channel
// in 8-bit display values (γ 2.2), ±1 for rounding.
inline void expectSkyBetweenZenithAndHorizon(const Image8& png, int x, int y, const glm::dvec3& zenithDisplay) {
  const glm::dvec3 white(0.75, 0.8, 0.85);
  for (int c = 0; c < 3; ++c) {
    const double zenith = std::pow(zenithDisplay[c], 2.2);
    const double horizon = zenith + 0.55 * (white[c] - zenith);
    const double a = 255.0 * std::pow(zenith, 1.0 / 2.2), b = 255.0 * std::pow(horizon, 1.0 / 2.2);
    EXPECT_GE(png.at(x, y, c), std::floor(std::min(a, b)) - 1.0) << "channel " << c << " at " << x << ", " << y;
    EXPECT_LE(png.at(x, y, c), std::ceil(std::max(a, b)) + 1.0) << "channel " << c << " at " << x << ", " << y;
  }
}

}  // namespace forest::test
