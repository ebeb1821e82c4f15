// forest bench passes: the full-screen passes (shadow term, blur, lighting) against their floors —
// passes that only read what the real ones read (render::Frame::timePassFloors) — and the ways
// of computing the term against each other: at full resolution, at half resolution with the
// depth-aware upsample, and the blur off (lighting looks the term up). Views sampled along a camera
// path (the main walk by default), at several image sizes; the variants take turns on each view,
// and each variant's lit image is compared with the full-resolution one's. Writes passes.json and
// passes.md.
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <functional>
#include <memory>

#include "commands.hpp"
#include "forest/core/camera_path.hpp"
#include "forest/core/error.hpp"
#include "forest/core/files.hpp"
#include "forest/core/image.hpp"
#include "forest/core/image_difference.hpp"
#include "forest/core/log.hpp"
#include "forest/core/statistics.hpp"
#include "forest/gl/context.hpp"
#include "forest/gl/debug.hpp"
#include "bench_paths.hpp"
#include "run_output.hpp"

namespace forest::app {
namespace {

using Clock = std::chrono::steady_clock;
using nlohmann::ordered_json;

struct PassesOptions {
  GlOptions gl;
  std::string scene, path;
  std::string out = "out/bench-passes";
  int views = 24;
  int rounds = 3;
  std::vector<std::string> sizes{"1280x720", "640x360"};
  ModeOptions modes;
  bool quiet = false;
};

// A way of computing the term the lighting uses (the blur at the CLI's default, 3 px up to 10 m).
struct Variant {
  const char* name;
  double blur;
  int termScale;
};
constexpr Variant kVariants[] = {{"full", 3.0, 1}, {"half", 3.0, 2}, {"blur off", 0.0, 1}};
constexpr int kVariantCount = 3;

// What one variant measured over the views and rounds, and how its images differ from "full"'s.
struct VariantRun {
  std::vector<double> term, blur, lighting, fullScreen, frame;
  std::vector<double> meanDifference, differingShare;  // per view: mean |Δ| / 255 over channels; share of pixels > 8/255
  std::vector<double> ssim;                            // per view: mean SSIM (Wang et al. 2004) against "full"'s image
};

std::pair<int, int> parseSize(const std::string& size) {
  int w = 0, h = 0;
  char x = 0;
  if (std::sscanf(size.c_str(), "%d%c%d", &w, &x, &h) != 3 || x != 'x' || w < 16 || h < 16 || w > 8192 || h > 8192)
    throw InputError(fmt::format("--sizes {}: expected WIDTHxHEIGHT, 16 to 8192 each (e.g. 1280x720)", size));
  return {w, h};
}

// The floors as bench passes reports them: render::PassFloorTimes' and half-resolution lighting's.
constexpr int kFloorCount = 8;
constexpr const char* kFloorNames[kFloorCount] = {"empty", "G-buffer", "G-buffer + half-res term", "G-buffer blocks (half res)",
                                                  "3 term texels (half res)", "G-buffer blocks + map lookup (half res)",
                                                  "G-buffer + map lookup", "half-res lighting's reads"};

// The share of an image's pixels with a surface nearer than eye depth `z` (reversed-Z depths; 0:
// the sky).
double shareNearerThan(const std::vector<float>& depth, const Camera& camera, double z) {
  long nearer = 0;
  for (const float d : depth) nearer += d > 0.0f && camera.eyeDepthOfReversedZ(d) < z ? 1 : 0;
  return depth.empty() ? 0.0 : static_cast<double>(nearer) / static_cast<double>(depth.size());
}

// One image size: every view rendered by each variant in turn (the order rotating per round), the
// floors timed on each view's G-buffer.
struct SizeRun {
  int width = 0, height = 0;
  VariantRun variants[kVariantCount];
  std::vector<double> floors[kFloorCount];  // render::PassFloorTimes' in order, then half-resolution lighting's
};

SizeRun runSize(const PassesOptions& options, const Scene& scene, const CameraPath& path, const gl::Context& context, int width,
                int height, const std::function<void()>& tick) {
  SizeRun run{width, height, {}, {}};
  render::Frame frame(scene, width, height);
  const double aspect = static_cast<double>(width) / height, fps = 30.0;
  const std::vector<Camera> all = filePath(path, scene, *frame.terrain(), path.frameCount(fps), fps, aspect);
  for (int round = 0; round < options.rounds; ++round)
    for (int v = 0; v < options.views; ++v) {
      const Camera& camera = all[static_cast<size_t>(v) * (all.size() - 1) / std::max(1, options.views - 1)];
      Image8 reference;
      for (int k = 0; k < kVariantCount; ++k) {
        const int i = (k + round) % kVariantCount;
        render::FrameSettings settings;
        options.modes.resolve(settings, context.info());
        settings.casters = render::defaultCasterSelection(context.info());
        settings.blurRadius = kVariants[i].blur;
        settings.shadowTermScale = kVariants[i].termScale;
        settings.keepShadowTerm = false;
        frame.resetHistory();
        frame.render(camera, 0.0, settings);  // settles CHC and the shadow setup on this view
        const render::FrameStats s = renderWithPassTimes(frame, camera, 0.0, settings);
        VariantRun& r = run.variants[i];
        const double fullScreen = s.passMs[FramePass::ShadowTerm] + s.passMs[FramePass::Blur] + s.passMs[FramePass::Lighting];
        r.term.push_back(s.passMs[FramePass::ShadowTerm]);
        r.blur.push_back(s.passMs[FramePass::Blur]);
        r.lighting.push_back(s.passMs[FramePass::Lighting]);
        r.fullScreen.push_back(fullScreen);
        r.frame.push_back(s.passMs.total());
        if (round == 0) {  // the variants in order: "full" first
          Image8 image = frame.readColor();
          if (i == 0) {
            reference = std::move(image);
          } else {
            const PixelDifference d = pixelDifference(reference, image);
            r.meanDifference.push_back(d.meanAbsolute);
            r.differingShare.push_back(d.shareOver8);
            r.ssim.push_back(meanSsim(reference, image));
          }
        }
        if (i == 0) {
          const render::PassFloorTimes f = frame.timePassFloors(3);
          // Half resolution's lighting reads the G-buffer and the term's gather nearer than the
          // half term's depth, the G-buffer and the map beyond (and on the sky): its floor is the
          // two floors weighed by the view's pixels on each side.
          settings.blurRadius = kVariants[1].blur;
          const double near = shareNearerThan(frame.readDepth(), camera, render::halfTermSplitDepth(settings));
          const double halfLighting = near * f.gbufferAndTermMs + (1.0 - near) * f.gbufferAndMapMs;
          int j = 0;
          for (const double ms : {f.emptyMs, f.gbufferMs, f.gbufferAndTermMs, f.gbufferBlocksMs, f.termTapsMs, f.gbufferBlocksAndMapMs,
                                  f.gbufferAndMapMs, halfLighting})
            run.floors[j++].push_back(ms);
        }
      }
      tick();
    }
  return run;
}

double p50(const std::vector<double>& v) { return percentile(v, 0.5); }
double mean(const std::vector<double>& v) { return Statistic{true}.of(v); }
double largest(const std::vector<double>& v) { return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end()); }
double smallest(const std::vector<double>& v) { return v.empty() ? 0.0 : *std::min_element(v.begin(), v.end()); }

// The size's table (Markdown) and JSON: per variant the passes' p50, the images' difference from
// "full"; the floors; the ratios the targets are stated in.
std::string reportSize(const SizeRun& run, const PassesOptions& options, ordered_json& json) {
  std::string md = fmt::format("\n### {}x{} ({} views x {} rounds)\n\n", run.width, run.height, options.views, options.rounds);
  md += "| variant | term ms | blur ms | lighting ms | term + blur + lighting | frame ms | image vs full: mean, max over views | pixels > 8/255: mean, max | SSIM vs full: mean, min |\n";
  md += "|---|---|---|---|---|---|---|---|---|\n";
  ordered_json size = {{"width", run.width}, {"height", run.height}};
  for (int i = 0; i < kVariantCount; ++i) {
    const VariantRun& r = run.variants[i];
    // "full" is the reference: SSIM 1 against itself (identical images).
    const double ssimMean = i == 0 ? 1.0 : mean(r.ssim), ssimMin = i == 0 ? 1.0 : smallest(r.ssim);
    md += fmt::format("| {} | {:.2f} | {:.2f} | {:.2f} | **{:.2f}** | {:.1f} | {} | {} | {} |\n", kVariants[i].name, p50(r.term), p50(r.blur),
                      p50(r.lighting), p50(r.fullScreen), p50(r.frame),
                      i == 0 ? "—" : fmt::format("{:.3f}, {:.3f} /255", mean(r.meanDifference), largest(r.meanDifference)),
                      i == 0 ? "—" : fmt::format("{:.3f}%, {:.3f}%", 100.0 * mean(r.differingShare), 100.0 * largest(r.differingShare)),
                      i == 0 ? "—" : fmt::format("{:.5f}, {:.5f}", ssimMean, ssimMin));
    size["variants"][kVariants[i].name] = {{"term_ms_p50", p50(r.term)},           {"blur_ms_p50", p50(r.blur)},
                                           {"lighting_ms_p50", p50(r.lighting)},   {"full_screen_ms_p50", p50(r.fullScreen)},
                                           {"frame_ms_p50", p50(r.frame)},         {"mean_difference_255", mean(r.meanDifference)},
                                           {"max_mean_difference_255", largest(r.meanDifference)},
                                           {"differing_share_mean", mean(r.differingShare)},
                                           {"differing_share_max", largest(r.differingShare)},
                                           {"ssim_mean", ssimMean},
                                           {"ssim_min", ssimMin}};
  }
  md += "\nFloors (p50 ms): ";
  for (int j = 0; j < kFloorCount; ++j) {
    md += fmt::format("{}{} {:.2f}", j ? ", " : "", kFloorNames[j], p50(run.floors[j]));
    size["floors_ms_p50"][kFloorNames[j]] = p50(run.floors[j]);
  }
  const VariantRun &full = run.variants[0], &half = run.variants[1], &off = run.variants[2];
  const double ratios[] = {p50(half.fullScreen) / p50(full.fullScreen), p50(half.frame) / p50(full.frame),
                           p50(half.term) / p50(run.floors[5]), p50(half.blur) / (2.0 * p50(run.floors[4])),
                           p50(half.lighting) / p50(run.floors[7]), p50(off.lighting) / p50(run.floors[6])};
  md += fmt::format(".\n\nhalf / full: term + blur + lighting **{:.3f}**, frame {:.3f}. Over the floor of its reads: half's term {:.2f}, "
                    "half's blur (two passes) {:.2f}, half's lighting {:.2f}; blur off, lighting {:.2f}.\n",
                    ratios[0], ratios[1], ratios[2], ratios[3], ratios[4], ratios[5]);
  size["ratios"] = {{"half_over_full_full_screen", ratios[0]}, {"half_over_full_frame", ratios[1]},
                    {"half_term_over_floor", ratios[2]},       {"half_blur_over_floor", ratios[3]},
                    {"half_lighting_over_floor", ratios[4]},   {"blur_off_lighting_over_floor", ratios[5]}};
  json["sizes"].push_back(size);
  return md;
}

int runBenchPasses(const PassesOptions& options) {
  const std::string scenePath = sceneFileOr(options.scene), pathFile = walkPathOr(options.path);
  const Scene scene = loadScene(scenePath);
  const CameraPath path = CameraPath::load(pathFile);
  if (!scene.terrain) throw InputError(fmt::format("{}: bench passes needs a scene with terrain (the camera path follows it)", scenePath));
  std::vector<std::pair<int, int>> sizes;
  for (const std::string& size : options.sizes) sizes.push_back(parseSize(size));
  const std::filesystem::path out = options.out;
  std::filesystem::create_directories(out);
  auto context = options.gl.open();
  const std::string device = gl::describe(context->info());
  const int total = static_cast<int>(sizes.size()) * options.views * options.rounds;
  int done = 0;
  const auto start = Clock::now();
  const std::function<void()> tick = [&] {
    showProgress("bench passes", "views", ++done, total, std::chrono::duration<double>(Clock::now() - start).count(), options.quiet);
  };
  ordered_json json = {{"device", device}, {"scene", scenePath}, {"path", pathFile}, {"views", options.views}, {"rounds", options.rounds}};
  std::string md = "# Full-screen passes against their floors\n\n" + benchmarkStamp(device) +
                   fmt::format("\n\n`forest bench passes` on {} along {}: the shadow term at full resolution (full), at half resolution "
                               "with the depth-aware upsample (half), and the blur off (lighting looks the term up); blur 3 px up to 10 m. "
                               "The variants take turns on each view; p50 over views and rounds. Floors: passes that only read what the "
                               "real ones read (shaders/pass_floor.frag).\n",
                               shownPath(scenePath), shownPath(pathFile));
  for (const auto& [width, height] : sizes) md += reportSize(runSize(options, scene, path, *context, width, height, tick), options, json);
  if (gl::debugErrorCount() > 0) throw Error(fmt::format("{} GL errors (first: {})", gl::debugErrorCount(), gl::debugErrorMessages().front()));
  writeFileAtomic(out / "passes.json", json.dump(2) + "\n");
  writeFileAtomic(out / "passes.md", md);
  std::cout << md << fmt::format("\nwrote {0}/passes.json, {0}/passes.md\n", shownPath(out));
  return 0;
}

}  // namespace

Run addPassesBenchCommand(CLI::App& bench) {
  auto options = std::make_shared<PassesOptions>();
  CLI::App* command = bench.add_subcommand(
      "passes",
      "The full-screen passes (shadow term, blur, lighting) against their floors (passes that only read what\n"
      "they read), with the term at full resolution, at half resolution with a depth-aware upsample, and the\n"
      "blur off; views along a camera path, the variants taking turns; each variant's image compared with\n"
      "the full-resolution one's. Writes passes.json and passes.md");
  options->gl.add(*command);
  command->add_option("--scene", options->scene, "Scene file (default: data/scenes/forest.toml)");
  command->add_option("--path", options->path, "Camera path (default: data/paths/walk.toml)")->check(CLI::ExistingFile);
  command->add_option("--views", options->views, "Views spread evenly along the path (2 to 1000)")->check(CLI::Range(2, 1000))->capture_default_str();
  command->add_option("--rounds", options->rounds, "Times each view is rendered by each variant (1 to 100)")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
  command->add_option("--sizes", options->sizes, "Image sizes (comma-separated WIDTHxHEIGHT)")->delimiter(',')->capture_default_str();
  options->modes.add(*command);
  command->add_option("--out", options->out, "Output folder (created when missing)")->check(outputFolder())->capture_default_str();
  command->add_flag("--quiet", options->quiet, "No progress bar");
  return [options] { return runBenchPasses(*options); };
}

}  // namespace forest::app
