#pragma once
// Subcommands of the `forest` program. Each registers its options on the CLI and returns the
// function that runs it (exit code).
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "forest/render/frame.hpp"

namespace forest::app {

using Run = std::function<int()>;

// Options every GL-using subcommand has.
struct GlOptions {
  std::string backend = "auto";
  void add(CLI::App& command);
};

// The frame's settings as flags (render, walkthrough).
struct FrameOptions {
  std::string method = "lispsm";
  int shadowSize = 2048;
  std::string culling = "chc++";
  int pcf = 0;
  double blur = 0.0;         // eye-space blur radius, pixels (0: off)
  double blurDepth = 10.0;   // metres up to which the full radius applies
  void add(CLI::App& command);
  render::FrameSettings settings() const;  // throws InputError for names the checks let through
};

// The walkthrough (main job) and what `forest budget` runs.
struct WalkthroughOptions {
  GlOptions gl;
  std::string scene;
  std::string path;
  std::string out = "out/walkthrough";
  int width = 1280;
  int height = 720;
  double fps = 30.0;
  int warmup = 0;  // first frames rendered but left out of the summary
  int frames = 0;  // 0: the whole path
  int every = 10;  // write every k-th frame as PNG
  FrameOptions frame;
  bool quiet = false;
};
// Renders the path; writes frames, contact sheet, report.json (with its summary) into out.
int runWalkthrough(const WalkthroughOptions& options);

// The interactive window (`walkthrough --window`): GLFW window, mouse look and WASD, keys for the
// frame's settings, the sun and freezing culling, a stats line and help; or driven by an input
// script. Writes report.json (each frame with its settings and stats line), the last window image
// and, with `record`, the camera path flown (replayable with --path).
struct WindowOptions {
  std::string script;  // input script (core/input_script.hpp); empty: interactive
  std::string record;  // camera path file to write; empty: none
};
int runWindow(const WalkthroughOptions& options, const WindowOptions& window);

// report.json of walkthrough and window runs: the passes in frame order, one record per frame,
// the summary (mean, p50, p95, p99 of frame, passes, triangles, casters, queries over the frames
// not marked warm-up) and its table on stdout.
inline constexpr const char* kPassNames[] = {"geometry", "shadow_setup", "shadow", "shadow_term", "blur", "lighting"};
nlohmann::ordered_json frameRecord(int index, double time, bool warmup, const Camera& camera, double yawDeg, double frameMs,
                                   const render::FrameStats& stats);
nlohmann::ordered_json summariseFrames(const nlohmann::ordered_json& records, int measured);
void printSummary(const nlohmann::ordered_json& summary);

// A walker's path through a terrain scene: from the scene's start, 1.4 m per frame along the view,
// turning 0.8° per frame, camera.above_ground (or 1.7 m) over the ground.
std::vector<Camera> walkPath(const Scene& scene, const terrain::Terrain& terrain, int frames, double aspect);

// The base scene with `trees` trees at the base scene's density: the terrain side grows with
// √(trees / base count), its sample spacing kept; LOD0 trees of `lod0` triangles.
Scene scaledScene(const Scene& base, int trees, int lod0);

// The scene file given, or the default forest (data/scenes/forest.toml, 5000 trees) when empty.
std::string sceneFileOr(const std::string& given);

// Resident memory of this process, MiB (/proc/self/statm).
double residentMegabytes();

// A progress line on stderr: a bar with ETA redrawn in place on a terminal, else a line at every
// tenth and at the end. Nothing when quiet.
void showProgress(std::string_view what, std::string_view unit, int done, int total, double elapsedSeconds, bool quiet);

// Linear-interpolated percentile p ∈ [0, 1] of the values (0 for none).
double percentile(std::vector<double> values, double p);

Run addInfoCommand(CLI::App& app);
Run addRenderCommand(CLI::App& app);
Run addTruthCommand(CLI::App& app);
Run addCheckCommand(CLI::App& app);
Run addStabilityCommand(CLI::App& app);
Run addBenchCommand(CLI::App& app);
// `forest bench speed-error`, registered under `bench`.
Run addSpeedErrorCommand(CLI::App& bench);
Run addWalkthroughCommand(CLI::App& app);
Run addBudgetCommand(CLI::App& app);
Run addStressCommand(CLI::App& app);

}  // namespace forest::app
