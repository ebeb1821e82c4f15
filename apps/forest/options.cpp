// The command-line flags several commands share, each defined once (name, range, help), and the
// checks every numeric flag gets (finite, in range) — so `render`, `walkthrough`, `budget`,
// `stress` and the benches agree on what a flag means and accepts.
#include <fmt/format.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>

#include "commands.hpp"
#include "forest/core/files.hpp"
#include "forest/core/log.hpp"

namespace forest::app {

namespace {

// Rejects values that parse as numbers but are not finite ("nan", "inf", "1e999"); everything else
// is left to the option's own conversion and range check.
CLI::Validator finiteNumber() {
  return CLI::Validator(
      [](std::string& value) -> std::string {
        char* end = nullptr;
        errno = 0;
        const double v = std::strtod(value.c_str(), &end);
        if (end != value.c_str() && *end == '\0' && (!std::isfinite(v) || errno == ERANGE))
          return fmt::format("value {} is not a finite number", value);
        return {};
      },
      "", "finite");
}

}  // namespace

CLI::Validator outputFolder() {
  return CLI::Validator([](std::string& folder) { return whyFolderIsNotWritable(folder); }, "", "output folder");
}

CLI::Validator outputFile() {
  return CLI::Validator([](std::string& file) { return whyFileIsNotWritable(file); }, "", "output file");
}

void requireFiniteNumbers(CLI::App& app) {
  for (CLI::Option* option : app.get_options()) {
    if (option->get_expected_min() > 0) option->check(finiteNumber());
  }
  for (CLI::App* command : app.get_subcommands({})) requireFiniteNumbers(*command);
}

void GlOptions::add(CLI::App& command) {
  command.add_option("--gl", backend,
                     "GL backend: auto (EGL, then OSMesa), egl (GPU device or Mesa surfaceless), "
                     "osmesa, window (GLFW; needs a display)")
      ->check(CLI::IsMember({"auto", "egl", "osmesa", "window"}))
      ->capture_default_str();
}

std::unique_ptr<gl::Context> GlOptions::open(int width, int height) const {
  gl::ContextOptions options;
  options.backend = gl::kBackendNames.parse(backend);
  if (width > 0) options.width = width;
  if (height > 0) options.height = height;
  auto context = gl::createContext(options);
  log::info("{}", gl::describe(context->info()));
  return context;
}

void ImageSizeOptions::add(CLI::App& command, const std::string& defaultNote) {
  CLI::Option* w = command.add_option("--width", width, "Image width in pixels (16 to 8192)" + defaultNote)->check(CLI::Range(16, 8192));
  CLI::Option* h = command.add_option("--height", height, "Image height in pixels (16 to 8192)" + defaultNote)->check(CLI::Range(16, 8192));
  if (defaultNote.empty()) {
    w->capture_default_str();
    h->capture_default_str();
  }
}

void RunLengthOptions::add(CLI::App& command, const std::string& framesMeaning) {
  framesOption = command.add_option("--frames", frames, "Frames to render (1 to 1000000; default: " + framesMeaning + ")")
                     ->check(CLI::Range(1, 1000000));
  warmupOption = command.add_option("--warmup", warmup,
                                    fmt::format("Frames rendered first but left out of the statistics (0 to 1000000; caches, CHC history;\n"
                                                "default {}, at most half of a shorter run)",
                                                warmup))
                     ->check(CLI::Range(0, 1000000));
  command.add_flag("--quiet", quiet, "No progress bar");
}

int RunLengthOptions::warmupFor(int total) const {
  const bool given = warmupOption != nullptr && warmupOption->count() > 0;
  return given ? warmup : std::min(warmup, total / 2);
}

void FrameOptions::add(CLI::App& command, bool withCulling) {
  command.add_option("--method", method, "Shadow method")
      ->check(CLI::IsMember(shadows::kShadowMethodNames.names()))
      ->capture_default_str();
  command.add_option("--shadow-size", shadowSize, "Shadow map texels per side (512 to 8192)")
      ->check(CLI::Range(512, 8192))
      ->capture_default_str();
  if (withCulling) {
    command.add_option("--culling", culling, "Culling strategy")
        ->check(CLI::IsMember(culling::kCullingStrategyNames.names()))
        ->capture_default_str();
  }
  cascadesOption = command.add_option("--cascades", cascades,
                                      "Z-partitioned shadows: slices of the visible depth range, each with its own\n"
                                      "map layer of --shadow-size² (1 to 4; 1: one map; default: the scene's [shadows])")
                       ->check(CLI::Range(1, shadows::kMaxCascades));
  splitLambdaOption = command.add_option("--split-lambda", splitLambda,
                                         "Split scheme (Zhang et al. 2006 eq. 4): 1 logarithmic, 0 uniform (0 to 1;\n"
                                         "default: the scene's [shadows], else 0.8)")
                          ->check(CLI::Range(0.0, 1.0));
  cascadeBlendOption = command.add_option("--cascade-blend", cascadeBlend,
                                          "Band beyond each split where the nearer slice fades into the farther, as a\n"
                                          "share of the split's distance (0 to 0.5; 0: hard; default: the scene's, else 0.1)")
                           ->check(CLI::Range(0.0, 0.5));
  command.add_option("--far-slice-scale", farSliceScale,
                     "Unequal layers: with --cascades K > 1 the last slice's layer has this many times\n"
                     "--shadow-size texels per side (0.5 to 2; 1: equal layers). For equal total texels T²,\n"
                     "--shadow-size T / sqrt(K - 1 + scale²). Not with --casters receiver-mask-gpu")
      ->check(CLI::Range(0.5, 2.0))
      ->capture_default_str();
  command.add_option("--pcf", pcf, "Wider PCF: (2r+1)² hardware 2×2 lookups (0 to 4; 0: one)")->check(CLI::Range(0, 4))->capture_default_str();
  casters.add(command);
  command.add_option("--blur", blur,
                     "Eye-space blur of the shadow term (thesis §9.4.2): radius in pixels (0 to 16) up to\n"
                     "--blur-depth, then shrinking as 1/depth (0: off)")
      ->check(CLI::Range(0.0, 16.0))
      ->capture_default_str();
  command.add_option("--blur-depth", blurDepth, "Depth (m, 0.01 to 10000) up to which the blur has its full radius")
      ->check(CLI::Range(0.01, 1e4))
      ->capture_default_str();
  command.add_option("--term-resolution", termResolution,
                     "Resolution of the shadow term the blur smooths: full (a lookup at every pixel, the blur's\n"
                     "vertical half in the lighting pass) or half (a lookup per 2x2 block at its nearest\n"
                     "surface, both blur halves on a quarter of the pixels, a depth-aware upsample in the\n"
                     "lighting pass); the blur off, the term is looked up at every pixel")
      ->check(CLI::IsMember({"full", "half"}))
      ->capture_default_str();
  command.add_option("--keep-slices", keepSlices,
                     "Kept shadow maps: each slice keeps its matrices while the view's focus body fits in\n"
                     "them and their texels stay within 1.25x a fresh fit's, so shadow edges hold still as\n"
                     "the camera moves (on); a refit also covers the camera's motion continued 8 frames, the\n"
                     "warp snapped. off: every slice refits to the view every frame (a frame alone: the same)")
      ->check(CLI::IsMember({"off", "on"}))
      ->capture_default_str();
  command.add_option("--hidden-casters", hiddenCasters,
                     "Trees hidden from the sun with receiver-pixels casters: cull (the trees that counted in\n"
                     "the last frame's map drawn first, the layer read back, every other tree drawn only where\n"
                     "it may come nearer the light at a texel a receiver beyond it reads), draw (all that the\n"
                     "receiver mask keeps), or auto (cull where the other trees' triangles outweigh the layer's\n"
                     "read-backs and their test, each priced at what it took when a layer was last culled).\n"
                     "The term is the same")
      ->check(CLI::IsMember({"auto", "cull", "draw"}))
      ->capture_default_str();
  command.add_option("--impostors", impostors,
                     "Far trees as impostors: on draws each tree beyond --impostor-distance by a quad textured\n"
                     "from its species' mesh baked from 256 directions (depth, albedo, normal; facing the sun\n"
                     "in the shadow map), cross-faded from the mesh over the next 10%; off: meshes only.\n"
                     "The truth still traces every tree's mesh. Not with --cache-slices")
      ->check(CLI::IsMember({"off", "on"}))
      ->capture_default_str();
  command.add_option("--impostor-distance", impostorDistance,
                     "Metres from the eye to a tree's base, over its size class's scale (as the LOD bands),\n"
                     "beyond which --impostors on draws it as its impostor: 1 to 1000000, or auto (where an\n"
                     "impostor's largest error - a bake texel, or the parallax of the bake view up to 9\n"
                     "degrees off - covers at most one pixel of the frame)")
      ->check([](const std::string& value) -> std::string {
        if (value == "auto") return "";
        double metres = 0.0;
        if (!CLI::detail::lexical_cast(value, metres) || !(metres >= 1.0 && metres <= 1e6))
          return "expected auto or metres from 1 to 1000000, got " + value;
        return "";
      })
      ->capture_default_str();
  command.add_option("--cache-slices", cacheSlices,
                     "Cached shadow map layers: a slice whose map was kept and whose casters are as they were\n"
                     "drawn (the same LODs and terrain morphs, none moved, the wind's sway since under a\n"
                     "texel) is not redrawn; casters it lacks are drawn into it (on). staggered: slice k\n"
                     "also keeps held casters that changed for up to 2^k - 1 frames. off: every layer is\n"
                     "cleared and drawn every frame")
      ->check(CLI::IsMember({"off", "on", "staggered"}))
      ->capture_default_str();
  modes.add(command);
}

void CasterOptions::add(CLI::App& command) {
  command.add_option("--casters", casters,
                     "Shadow casters: of the visible receivers' boxes (receivers), of the visible sun-facing\n"
                     "pixels (receiver-pixels: the G-buffer read back, a CPU wait on a GPU), of those pixels\n"
                     "with the trees tested on the GPU (receiver-mask-gpu: nothing read back), of the frustum's\n"
                     "focus body (frustum-body), all, or auto (receiver-pixels on a software renderer such as\n"
                     "llvmpipe, whose rasteriser threads wait anyway while the CPU sets up the shadows; receivers\n"
                     "on a GPU)")
      ->check(CLI::IsMember({"auto", "receivers", "receiver-pixels", "receiver-mask-gpu", "frustum-body", "all"}))
      ->capture_default_str();
}

render::CasterSelection CasterOptions::resolve(const gl::ContextInfo& context) const {
  return casters == "auto" ? render::defaultCasterSelection(context) : render::kCasterSelectionNames.parse(casters);
}

void ModeOptions::add(CLI::App& command) {
  command.add_option("--timing", timing,
                     "Pass timing: profile (glFinish + clock around each pass; the pipeline is serialised),\n"
                     "queries (GL timestamp queries read frames later; nothing in a frame waits for the GPU),\n"
                     "auto (profile on a software renderer such as llvmpipe, queries on a GPU)")
      ->check(CLI::IsMember({"auto", "profile", "queries"}))
      ->capture_default_str();
  command.add_option("--queries", queries,
                     "How CHC/CHC++ read occlusion queries: deterministic (at points the traversal fixes: CHC\n"
                     "every 64 steps, CHC++ when its queue runs dry; the same visible set every run), async\n"
                     "(as soon as the fence of the query's draw has signalled), auto (deterministic on a software\n"
                     "renderer, async on a GPU); both are exact")
      ->check(CLI::IsMember({"auto", "deterministic", "async"}))
      ->capture_default_str();
}

void FrameOptions::resolveModes(render::FrameSettings& s, const gl::ContextInfo& context) const {
  modes.resolve(s, context);
  s.casters = casters.resolve(context);
}

render::FrameSettings FrameOptions::settings(const gl::ContextInfo& context) const {
  render::FrameSettings s;
  resolveModes(s, context);
  s.method = shadows::kShadowMethodNames.parse(method);
  s.shadowMapSize = shadowSize;
  s.culling = culling::kCullingStrategyNames.parse(culling);
  s.pcfRadius = pcf;
  s.blurRadius = blur;
  s.blurReferenceDepth = blurDepth;
  s.shadowTermScale = termResolution == "half" ? 2 : 1;
  s.keepSlices = keepSlices == "on";
  s.hiddenCasters = render::kHiddenCastersNames.parse(hiddenCasters);
  s.cacheSlices = cacheSlices != "off";
  s.staggerSlices = cacheSlices == "staggered";
  s.impostorDistance = impostors != "on" ? 0.0 : impostorDistance == "auto" ? render::kImpostorDistanceAuto : std::stod(impostorDistance);
  if (cascadesOption && cascadesOption->count() > 0) s.cascades = cascades;
  if (splitLambdaOption && splitLambdaOption->count() > 0) s.splitLambda = splitLambda;
  if (cascadeBlendOption && cascadeBlendOption->count() > 0) s.cascadeBlend = cascadeBlend;
  s.farSliceScale = farSliceScale;
  return s;
}

void ModeOptions::resolve(render::FrameSettings& s, const gl::ContextInfo& context) const {
  s.timing = timing == "auto" ? render::defaultTimingMode(context) : gl::kTimingModeNames.parse(timing);
  s.queries = queries == "auto" ? render::defaultQueryMode(context) : culling::kQueryModeNames.parse(queries);
}

nlohmann::ordered_json ModeOptions::json(const gl::ContextInfo& context) const {
  render::FrameSettings s;
  resolve(s, context);
  return {{"timing", gl::kTimingModeNames.name(s.timing)}, {"queries", culling::kQueryModeNames.name(s.queries)}};
}

render::FrameStats renderWithPassTimes(render::Frame& frame, const Camera& camera, double time, const render::FrameSettings& settings) {
  render::FrameStats stats = frame.render(camera, time, settings);
  if (stats.passTimesPending) {
    for (const gl::FrameTiming& t : frame.drainPassTimes())
      if (t.frame == stats.frameNumber) stats.setPassTimes(t);
    stats.passTimesPending = false;
  }
  return stats;
}

nlohmann::ordered_json FrameOptions::json(const gl::ContextInfo& context, const Scene& scene) const {
  const ShadowSettings c = render::resolveCascades(settings(), scene);
  nlohmann::ordered_json j = {{"method", method},
                              {"shadow_size", shadowSize},
                              {"cascades", c.cascades},
                              {"split_lambda", c.split_lambda},
                              {"cascade_blend", c.cascade_blend},
                              {"far_slice_scale", farSliceScale},
                              {"shadow_texels", render::shadowTexels(settings(), c.cascades)},
                              {"culling", culling},
                              {"casters", render::kCasterSelectionNames.name(settings(context).casters)},
                              {"pcf_radius", pcf},
                              {"blur_px", blur},
                              {"blur_depth_m", blurDepth},
                              {"term_resolution", termResolution},
                              {"keep_slices", keepSlices},
                              {"hidden_casters", hiddenCasters},
                              {"cache_slices", cacheSlices},
                              {"impostors", impostors},
                              {"impostor_distance_m", impostorDistance}};
  j.update(modes.json(context));
  return j;
}

void addSoftRaysOption(CLI::App& command, int& softRays) {
  command.add_option("--soft-rays", softRays, "Rays over the sun's disc per pixel for the soft-shadow truth (0 to 1024; 0: none)")
      ->check(CLI::Range(0, 1024))
      ->capture_default_str();
}

}  // namespace forest::app
