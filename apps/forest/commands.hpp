#pragma once
// Subcommands of the `forest` program. Each registers its options on the CLI and returns the
// function that runs it (exit code).
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "forest/core/statistics.hpp"  // percentile
#include "forest/render/frame.hpp"
#include "forest/truth/frame_truth.hpp"

namespace forest::app {

using Run = std::function<int()>;

// Flags shared by several commands, each defined once (options.cpp): names, ranges and help agree
// everywhere; each command sets its defaults before add().

// Every numeric flag of every command (recursively) must be finite: "nan", "inf" are usage errors.
void requireFiniteNumbers(CLI::App& app);

// Checks for an --out: a folder the command writes its files into, or one file. Run when the
// option is parsed, so a path that cannot be written is a usage error (one line, exit 2) before
// any scene is loaded (whyFolderIsNotWritable, whyFileIsNotWritable: nothing is left behind).
CLI::Validator outputFolder();
CLI::Validator outputFile();

// --gl: the GL backend.
struct GlOptions {
  std::string backend = "auto";
  void add(CLI::App& command);
  // A context of this backend (width × height for the backends that make a surface of that size;
  // 0: their default), its device logged.
  std::unique_ptr<gl::Context> open(int width = 0, int height = 0) const;
};

// --width, --height (16 to 8192). defaultNote non-empty: the defaults come from elsewhere (the
// scene, the budget file) and the note says so; 0 then means "not given".
struct ImageSizeOptions {
  int width = 1280;
  int height = 720;
  void add(CLI::App& command, const std::string& defaultNote = "");
};

// --frames (1 to 10^6; 0 = not given), --warmup, --quiet: how long a multi-frame command runs.
struct RunLengthOptions {
  int frames = 0;
  int warmup = 10;
  bool quiet = false;
  void add(CLI::App& command, const std::string& framesMeaning);
  // Warm-up frames of a run of `total` frames: --warmup when given, else the default capped at
  // half the run (so a short run still measures something).
  int warmupFor(int total) const;
  CLI::Option* framesOption = nullptr;
  CLI::Option* warmupOption = nullptr;
};

// --timing and --queries (DESIGN §9): how passes are timed and how occlusion queries are read, for
// every command that renders frames (through FrameOptions) and for the benches.
struct ModeOptions {
  std::string timing = "auto";   // auto: profile on a software renderer, queries on a hardware one
  std::string queries = "auto";  // auto: deterministic on a software renderer, async on a hardware one
  void add(CLI::App& command);
  // Sets the timing and query modes of `s` for the context (auto: render::defaultTimingMode,
  // render::defaultQueryMode).
  void resolve(render::FrameSettings& s, const gl::ContextInfo& context) const;
  // {"timing": …, "queries": …} as resolved for the context.
  nlohmann::ordered_json json(const gl::ContextInfo& context) const;
};

// --casters: which objects the shadow pass draws (render::CasterSelection), auto resolved by the
// renderer (render::defaultCasterSelection: the receiver pixels on a software renderer).
struct CasterOptions {
  std::string casters = "auto";
  void add(CLI::App& command);
  render::CasterSelection resolve(const gl::ContextInfo& context) const;  // throws InputError for a bad name
};

// Renders a frame; in the GpuQueries timing mode also waits (outside the frame) for its pass
// times, so a benchmark reads them from the returned stats in either mode.
render::FrameStats renderWithPassTimes(render::Frame& frame, const Camera& camera, double time, const render::FrameSettings& settings);

// The frame's settings as flags (render, truth, walkthrough, budget, stress). One default for all:
// the blur is on (3 px, thesis §9.4.2), so every command renders the same frame unless told.
struct FrameOptions {
  std::string method = "lispsm";
  int shadowSize = 2048;
  std::string culling = "chc++";
  int pcf = 0;
  double blur = 3.0;         // eye-space blur radius, pixels (0: off)
  double blurDepth = 10.0;   // metres up to which the full radius applies
  std::string termResolution = "half";  // of the blurred shadow term: full or half (FrameSettings::shadowTermScale)
  std::string keepSlices = "on";        // kept shadow maps: off or on (FrameSettings::keepSlices)
  std::string hiddenCasters = "auto";   // trees hidden from the sun: auto, cull or draw (FrameSettings::hiddenCasters)
  std::string cacheSlices = "off";      // cached shadow map layers: off, on or staggered (FrameSettings::cacheSlices, staggerSlices)
  std::string impostors = "off";        // far trees as impostors: off or on (FrameSettings::impostorDistance)
  std::string impostorDistance = "auto";  // metres (over the size class's scale) beyond which a tree is its impostor, or auto
  CasterOptions casters;
  // Z-partitioning; each left unset (the scene's [shadows]) unless its flag is given.
  int cascades = 1;
  double splitLambda = 0.8;
  double cascadeBlend = 0.1;
  double farSliceScale = 1.0;  // the last slice's layer side over the others' (FrameSettings::farSliceScale)
  CLI::Option* cascadesOption = nullptr;
  CLI::Option* splitLambdaOption = nullptr;
  CLI::Option* cascadeBlendOption = nullptr;
  ModeOptions modes;
  void add(CLI::App& command, bool withCulling = true);
  // The settings; timing and query modes resolved for the context (auto: render::defaultTimingMode,
  // render::defaultQueryMode).
  // Throws InputError for names the checks let through.
  render::FrameSettings settings(const gl::ContextInfo& context) const;
  render::FrameSettings settings() const { return settings(gl::ContextInfo{}); }  // before a context exists: checks only
  // Sets what `auto` may leave to the context in `s` — the timing and query modes and the
  // casters — as settings(context) does.
  void resolveModes(render::FrameSettings& s, const gl::ContextInfo& context) const;
  // The settings as report.json writes them (timing as resolved for the context; cascades as
  // resolved for the scene, with the total texels K · size²).
  nlohmann::ordered_json json(const gl::ContextInfo& context, const Scene& scene) const;
};

// --soft-rays for truth and bench speed-error (0 to 1024).
void addSoftRaysOption(CLI::App& command, int& softRays);

// The walkthrough (main job) and what `forest budget` runs.
inline constexpr int kBetweenFramesEvery = 20;  // WalkthroughOptions::betweenFrames' spacing

struct WalkthroughOptions {
  GlOptions gl;
  std::string scene;
  std::string path;
  std::string out = "out/walkthrough";
  ImageSizeOptions size;
  double fps = 30.0;
  RunLengthOptions length;  // frames 0: the whole path
  int every = 10;           // write every k-th frame as PNG
  bool video = false;       // walkthrough.mp4 of every frame (walkthrough: on unless --no-video; budget: off)
  FrameOptions frame;
  // Called in the run's GL context after every kBetweenFramesEvery-th frame, once its work is done (budget: times
  // the reference frame under the run's own load); its time is left out of the frames' intervals.
  // Unset: nothing.
  std::function<void()> betweenFrames;
  // The flags walkthrough and budget share (budget: without --every and --fps).
  void add(CLI::App& command, bool withFramesOut);
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
nlohmann::ordered_json frameRecord(int index, double time, bool warmup, const Camera& camera, double yawDeg, double frameMs,
                                   const render::FrameStats& stats);
// truth.json's `bands`: per distance band from_m, to_m (null: no end), lit_facing, misclassification.
nlohmann::ordered_json bandsJson(const std::vector<truth::DistanceBand>& bands);
// Each slice of a z-partitioned frame: from_m, to_m, n, gamma_deg, casters, triangles, shadow_ms.
nlohmann::ordered_json cascadesJson(const render::FrameStats& stats);
// GpuQueries timing: writes the pass times of frames whose timer queries finished into their
// report records (records[k] is frame k). Profiling: nothing to do.
void recordPassTimes(const std::vector<gl::FrameTiming>& timings, nlohmann::ordered_json& records);
nlohmann::ordered_json summariseFrames(const nlohmann::ordered_json& records, int measured);
void printSummary(const nlohmann::ordered_json& summary);
// report.json's `startup`: each step of building the frame's scene (render::StartupStep) as
// <step>_ms, total_ms, rss_mib and heap_mib after it, bytes_per_tree (the heap in use added after the terrain,
// per tree); and that as one line for stdout.
nlohmann::ordered_json startupRecord(const render::Frame& frame);
std::string startupLine(const nlohmann::ordered_json& startup);

// A walker's path through a terrain scene: from the scene's start, 1.4 m per frame along the view,
// turning 0.8° per frame, camera.above_ground (or 1.7 m) over the ground.
std::vector<Camera> walkPath(const Scene& scene, const terrain::Terrain& terrain, int frames, double aspect);

// A clearing beside the densest stand (vegetation::densestStand): the centre of the nearest 20 m cell at least 60 m from `stand` and 30 m
// inside `bounds` (the terrain's) with no tree in it or its 8 neighbours (`stand` when none is).
glm::dvec2 clearingNear(const vegetation::Forest& forest, const Aabb& bounds, const glm::dvec2& stand);

// The base scene with `trees` trees at the base scene's density: the terrain side grows with
// √(trees / base count), its sample spacing kept; LOD0 trees of `lod0` triangles.
Scene scaledScene(const Scene& base, int trees, int lod0);

// The scene file given, or the default forest (data/scenes/forest.toml, 5000 trees) when empty.
std::string sceneFileOr(const std::string& given);
// WalkthroughOptions::every of a run that writes its first frame only (budget; --every's maximum).
inline constexpr int kFirstFrameOnly = 1000000;

// A path as the console shows it, one way for every command: relative to the current folder when
// inside it (data/scenes/forest.toml), else absolute (/tmp/run, not ../../tmp/run).
std::string shownPath(const std::filesystem::path& path);
// The camera-path file given, or the main walk (data/paths/walk.toml) when empty.
std::string walkPathOr(const std::string& given);

// A progress line on stderr: a bar with ETA redrawn in place on a terminal, else a line at every
// tenth and at the end. Nothing when quiet.
void showProgress(std::string_view what, std::string_view unit, int done, int total, double elapsedSeconds, bool quiet);


Run addInfoCommand(CLI::App& app);
Run addRenderCommand(CLI::App& app);
Run addTruthCommand(CLI::App& app);
Run addCheckCommand(CLI::App& app);
Run addStabilityCommand(CLI::App& app);
Run addBenchCommand(CLI::App& app);
// `forest bench speed-error`, registered under `bench`.
Run addSpeedErrorCommand(CLI::App& bench);
Run addPassesBenchCommand(CLI::App& bench);  // command_bench_passes.cpp
Run addScaleBenchCommand(CLI::App& bench);   // command_bench_scale.cpp
Run addImpostorsBenchCommand(CLI::App& bench);  // command_bench_impostors.cpp
Run addWalkthroughCommand(CLI::App& app);
Run addBudgetCommand(CLI::App& app);
Run addStressCommand(CLI::App& app);

}  // namespace forest::app
