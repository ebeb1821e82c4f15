// forest render: one frame of a scene — culled geometry pass, shadow setup and pass, shadow term,
// lighting — written as an image, with a JSON record of the frame next to it.
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <limits>

#include "commands.hpp"
#include "forest/core/error.hpp"
#include "forest/core/files.hpp"
#include "forest/core/image.hpp"
#include "forest/core/log.hpp"
#include "forest/core/resources.hpp"
#include "forest/core/scene.hpp"
#include "forest/gl/context.hpp"
#include "forest/gl/debug.hpp"
#include "forest/render/debug_views.hpp"
#include "forest/render/frame.hpp"
#include "forest/truth/frame_truth.hpp"

namespace forest::app {
namespace {

struct RenderOptions {
  GlOptions gl;
  std::string scene;
  std::string out;
  std::string json;
  ImageSizeOptions size{0, 0};  // 0: the scene's render.width / height
  double time = 0.0;
  FrameOptions frame;
  double bias = 0.0;
  bool frontFaces = false;
  std::optional<double> fog;
  std::vector<double> camera;  // x y z yaw pitch
  std::vector<double> sun;     // x y z
  int framesBefore = 0;        // frames rendered at the same view before the one measured
  std::string debug;           // folder for the debug images (empty: none)
  // forest truth: evaluate the frame against the ray-traced truth, writing into truthFolder.
  std::string truthFolder;
  int softRays = 16;
};

// Single-channel float rows (bottom row first) as an image, top row first.
ImageF channelImage(const std::vector<float>& values, int width, int height) {
  ImageF image(width, height, 1);
  image.pixels = values;
  flipRows(image);
  return image;
}

// What the blur did, for the blurred term's picture: with the radius r px up to the reference depth
// d and r·d/z beyond, it stops moving a pixel where r·d/z < ½ (thesis §6.3).
std::string blurCaption(const std::vector<float>& term, const std::vector<float>& blurred, const render::FrameSettings& settings) {
  if (settings.blurRadius <= 0.0) return "after the blur: the blur is off (--blur 0), the same as shadow-term.png";
  std::size_t changed = 0;
  for (std::size_t i = 0; i < term.size(); ++i) changed += std::abs(blurred[i] - term[i]) > 1.0f / 255.0f ? 1 : 0;
  return fmt::format("after the blur: {:g} px up to {:g} m, r*{:g}/z beyond (none past {:.0f} m); {:.1f}% of the pixels changed",
                     settings.blurRadius, settings.blurReferenceDepth, settings.blurReferenceDepth,
                     2.0 * settings.blurRadius * settings.blurReferenceDepth, 100.0 * double(changed) / std::max<double>(1.0, double(term.size())));
}

// Shadow map (EXR and a picture with its scale), the slices picture, and the shadow term before
// and after the blur (EXR, and pictures captioned with what the blur changed).
void writeDebugImages(const render::Frame& frame, const Camera& camera, const glm::dvec3& sunDirection,
                      const render::FrameStats& stats, const render::FrameSettings& settings, const std::filesystem::path& folder) {
  for (int slice = 0; slice < frame.cascadeCount(); ++slice) {  // cascades: shadow-map-<slice>.*
    const int size = frame.shadowMapSize(slice);
    const std::string name = frame.cascadeCount() == 1 ? "shadow-map" : fmt::format("shadow-map-{}", slice);
    const std::vector<float> map = frame.readShadowMap(slice);
    writeImage(folder / (name + ".exr"), channelImage(map, size, size));
    writeImage(folder / (name + ".png"), render::shadowMapPicture(map, size));
  }
  writeImage(folder / "cascades.png", render::cascadesPicture(frame, camera, stats));
  const std::vector<float> term = frame.readShadowTerm(), blurred = frame.readBlurredShadowTerm();
  writeImage(folder / "shadow-term.exr", channelImage(term, frame.width(), frame.height()));
  writeImage(folder / "shadow-term-blurred.exr", channelImage(blurred, frame.width(), frame.height()));
  writeImage(folder / "shadow-term.png",
             render::captionedTerm(term, frame.width(), frame.height(), "shadow term before the blur (PCF): white lit, black shadow"));
  writeImage(folder / "shadow-term-blurred.png",
             render::captionedTerm(blurred, frame.width(), frame.height(), blurCaption(term, blurred, settings)));
  writeImage(folder / "top-down.png", render::topDownDiagram(frame, sunDirection));
}

}  // namespace

nlohmann::ordered_json bandsJson(const std::vector<truth::DistanceBand>& bands) {
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  for (const truth::DistanceBand& b : bands)
    out.push_back({{"from_m", b.fromM},
                   {"to_m", std::isinf(b.toM) ? nlohmann::ordered_json() : nlohmann::ordered_json(b.toM)},
                   {"lit_facing", b.litFacing},
                   {"misclassification", b.misclassification}});
  return out;
}

namespace {

// forest truth: the frame against the ray-traced truth; truth.json, error.png and a summary.
// "0–50 m 0.120% of 48211, 50–200 m …, 200 m+ …": each band's misclassification and lit-facing pixels.
std::string bandsLine(const std::vector<truth::DistanceBand>& bands) {
  std::string line;
  for (const truth::DistanceBand& b : bands) {
    const std::string range = std::isinf(b.toM) ? fmt::format("{:.0f} m+", b.fromM) : fmt::format("{:.0f}–{:.0f} m", b.fromM, b.toM);
    line += fmt::format("{}{} {:.3f}% of {}", line.empty() ? "" : ", ", range, 100.0 * b.misclassification, b.litFacing);
  }
  return line;
}

void writeTruth(const render::Frame& frame, const render::FrameStats& stats, const Scene& scene, const Camera& camera,
                const RenderOptions& options) {
  const std::filesystem::path folder = options.truthFolder;
  truth::TruthOptions truthOptions;
  truthOptions.softRays = options.softRays;
  const auto start = std::chrono::steady_clock::now();
  const truth::FrameError e = truth::evaluateFrame(frame, stats, scene, camera, options.time, truthOptions);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  writeImage(folder / "error.png", e.errorImage);
  auto stats3 = [](const shadows::ErrorStatistics& s) {
    return nlohmann::ordered_json{{"max", s.max}, {"p95", s.p95}, {"mean", s.mean}, {"samples", s.samples}};
  };
  nlohmann::ordered_json j;
  j["method"] = options.frame.method;
  j["shadow_size"] = options.frame.shadowSize;
  j["shadow_texels"] = render::shadowTexels(options.frame.settings(), stats.cascades);
  j["cascades"] = {{"count", stats.cascades}, {"splits_m", nlohmann::ordered_json::array()}, {"slices", cascadesJson(stats)}};
  for (int i = 0; i < stats.cascades; ++i) j["cascades"]["splits_m"].push_back(stats.cascade[static_cast<size_t>(i)].fromM);
  j["cascades"]["splits_m"].push_back(stats.cascade[static_cast<size_t>(stats.cascades - 1)].toM);  // z_f
  j["pixels"] = {{"total", e.pixels}, {"scored", e.scored}, {"lit_facing", e.litFacing}, {"near_edge", e.nearEdge}};
  j["misclassification"] = {{"all", e.misclassification},
                            {"near_edge", e.misclassificationNearEdge},
                            {"elsewhere", e.misclassificationElsewhere},
                            {"false_shadow", e.falseShadow},
                            {"false_light", e.falseLight}};
  j["bands"] = bandsJson(e.bands);
  const bool soft = options.softRays > 0;
  j["soft"] = {{"rays", options.softRays},
               {"sun_disc_deg", truthOptions.sunDiscDeg},
               {"blurred_mean_abs_error", soft ? nlohmann::ordered_json(e.softMeanAbsoluteError) : nlohmann::ordered_json()}};
  j["aliasing"] = {{"px_per_texel", stats3(e.aliasingPixels)}, {"perspective_relative", stats3(e.aliasingRelative)}};
  j["casters"] = {{"selected", e.casters.selected},
                  {"needed", e.casters.needed},
                  {"missing", e.casters.missing},
                  {"selected_triangles", e.casters.selectedTriangles},
                  {"needed_triangles", e.casters.neededTriangles},
                  {"missing_objects", e.casters.missingObjects}};
  j["frame_ms"] = stats.passMs.total();
  j["shadow_pass_ms"] = stats.passMs[FramePass::Shadow];
  j["truth_seconds"] = seconds;
  writeFileAtomic(folder / "truth.json", j.dump(2) + "\n");
  std::cout << fmt::format(
      "truth ({:.1f} s): {} lit-facing pixels scored; misclassified {:.3f}% (near edges {:.3f}%, elsewhere {:.3f}%; "
      "false shadow {:.3f}%, false light {:.3f}%)\n"
      "  by distance: {}\n"
      "  soft shadow: {}\n"
      "  aliasing: {:.2f} / {:.2f} / {:.2f} px per texel (max / p95 / mean)\n"
      "  casters: {} selected ({} triangles), {} needed by the oracle ({} triangles), {} missing{}\n"
      "  wrote {} and {}\n",
      seconds, e.litFacing, 100 * e.misclassification, 100 * e.misclassificationNearEdge, 100 * e.misclassificationElsewhere,
      100 * e.falseShadow, 100 * e.falseLight, bandsLine(e.bands),
      soft ? fmt::format("blurred term vs {}-ray sun disc, mean |error| {:.4f}", options.softRays, e.softMeanAbsoluteError)
           : std::string("not measured (--soft-rays 0)"),
      e.aliasingPixels.max,
      e.aliasingPixels.p95, e.aliasingPixels.mean, e.casters.selected, e.casters.selectedTriangles, e.casters.needed,
      e.casters.neededTriangles, e.casters.missing,
      // Culling crowns behind others from the sun: the oracle names the one nearer the pixel.
      e.casters.missing > 0 ? " (hidden from the sun behind crowns drawn)" : "",
      shownPath(folder / "truth.json"), shownPath(folder / "error.png"));
}

int runRender(const RenderOptions& options) {
  const std::string scenePath = sceneFileOr(options.scene);  // the forest, as every command
  Scene scene = loadScene(scenePath);
  if (options.size.width > 0) scene.render.width = options.size.width;
  if (options.size.height > 0) scene.render.height = options.size.height;
  if (!options.camera.empty() && !(std::abs(options.camera[4]) <= 90.0))
    throw InputError(fmt::format("--camera: pitch {}: expected -90 to 90 degrees", options.camera[4]));
  if (!options.sun.empty()) {
    const glm::dvec3 d(options.sun[0], options.sun[1], options.sun[2]);
    if (!(glm::length(d) > 0.0) || !std::isfinite(glm::length(d))) throw InputError("--sun: expected a finite non-zero direction");
    scene.sun.direction = glm::normalize(d);
  }
  render::FrameSettings settings = options.frame.settings();
  settings.slopeScaleBias = options.bias;
  settings.backside = !options.frontFaces;
  settings.fogDensity = options.fog;

  auto context = options.gl.open(scene.render.width, scene.render.height);
  options.frame.resolveModes(settings, context->info());

  render::Frame frame(scene, scene.render.width, scene.render.height);
  Camera camera = frame.startCamera();
  if (!options.camera.empty()) {
    camera.position = {options.camera[0], options.camera[1], options.camera[2]};
    camera.yaw = glm::radians(options.camera[3]);
    camera.pitch = glm::radians(options.camera[4]);
  }
  for (int k = 0; k < options.framesBefore; ++k) frame.render(camera, options.time, settings);
  render::FrameStats stats = frame.render(camera, options.time, settings);
  for (const gl::FrameTiming& t : frame.drainPassTimes()) stats.setPassTimes(t);  // timer queries: wait for this frame's
  const Image8 image = frame.readColor();
  if (gl::debugErrorCount() > 0) {
    throw Error(fmt::format("{} GL errors while rendering (first: {})", gl::debugErrorCount(),
                            gl::debugErrorMessages().front()));
  }
  writeImage(options.out, image);
  if (!options.debug.empty()) writeDebugImages(frame, camera, scene.sun.direction, stats, settings, options.debug);
  if (!options.truthFolder.empty()) writeTruth(frame, stats, scene, camera, options);

  nlohmann::ordered_json j;
  j["scene"] = scenePath;
  j["image"] = options.out;
  j["device"] = gl::describe(context->info());
  j["resolution"] = {image.width, image.height};
  j["camera"] = {{"position", {camera.position.x, camera.position.y, camera.position.z}},
                 {"yaw_deg", glm::degrees(camera.yaw)},
                 {"pitch_deg", glm::degrees(camera.pitch)}};
  const ShadowSettings cascades = render::resolveCascades(settings, scene);
  j["settings"] = {{"method", options.frame.method}, {"shadow_size", options.frame.shadowSize},
                   {"cascades", cascades.cascades}, {"split_lambda", cascades.split_lambda},
                   {"cascade_blend", cascades.cascade_blend}, {"far_slice_scale", settings.farSliceScale},
                   {"shadow_texels", render::shadowTexels(settings, cascades.cascades)},
                   {"culling", options.frame.culling}, {"casters", render::kCasterSelectionNames.name(settings.casters)},
                   {"slope_bias", options.bias},       {"backside", settings.backside},
                   {"pcf_radius", options.frame.pcf},  {"blur_px", options.frame.blur},
                   {"fog", options.fog.value_or(scene.render.haze)},               {"timing", gl::kTimingModeNames.name(settings.timing)},
                   {"queries", culling::kQueryModeNames.name(settings.queries)}};
  for (FramePass pass : kFramePassNames.values()) j["passes_ms"][std::string(kFramePassNames.name(pass))] = stats.passMs[pass];
  j["geometry"] = {{"visible_objects", stats.visibleObjects},
                   {"triangles", stats.geometryTriangles},
                   {"queries", stats.culling.queriesIssued},
                   {"objects_drawn", stats.culling.objectsDrawn},
                   {"impostor_distance_m", stats.impostorDistance}};
  j["shadow"] = {{"casters", stats.casterObjects},
                 {"triangles", stats.shadowTriangles},
                 {"terrain_triangles", stats.shadowTerrainTriangles},
                 {"n", stats.shadow.n},
                 {"gamma_deg", stats.shadow.gammaDeg},
                 {"fallback", stats.shadow.fallback},
                 {"sun_below_horizon", stats.sunBelowHorizon}};
  j["z_f"] = stats.farDepth;
  j["n_optimal"] = stats.shadow.nOptimal;
  j["nearest_depth_m"] = stats.nearestDepth;
  j["cascades"] = cascadesJson(stats);
  const std::string jsonPath =
      options.json.empty() ? std::filesystem::path(options.out).replace_extension(".json").string() : options.json;
  writeFileAtomic(jsonPath, j.dump(2) + "\n");
  std::cout << fmt::format(
      "wrote {} and {} ({}x{}): {} visible objects, {} triangles; shadow {} {} with {} casters, {} triangles; "
      "z_f {:.1f} m, n {:.2f}, γ {:.1f}°{}\n",
      shownPath(options.out), shownPath(jsonPath), image.width, image.height, stats.visibleObjects, stats.geometryTriangles, options.frame.method,
      render::shadowLayoutLabel(settings, cascades.cascades), stats.casterObjects, stats.shadowTriangles, stats.farDepth, stats.shadow.n, stats.shadow.gammaDeg,
      stats.sunBelowHorizon ? " (sun below the horizon: ambient only)" : "");
  return 0;
}

// The scene, camera and frame flags render and truth share.
void addFrameInputs(CLI::App* command, RenderOptions* options) {
  options->gl.add(*command);
  command->add_option("--scene", options->scene, "Scene file (TOML; default: data/scenes/forest.toml)");
  options->size.add(*command, " (default: the scene's render.width / height)");
  command->add_option("--time", options->time, "Seconds since the start (wind sway; 0 to 10^6)")
      ->check(CLI::Range(0.0, 1e6))
      ->capture_default_str();
  command->add_option("--camera", options->camera, "Camera pose: x y z yaw_deg pitch_deg (default: the scene's; pitch -90 to 90)")
      ->expected(5);
  command->add_option("--sun", options->sun, "Sun direction x y z, the way light travels (default: the scene's)")
      ->expected(3);
  command->add_option("--frames-before", options->framesBefore,
                      "Frames rendered at the same view before the one measured, so that it starts from what a\n"
                      "frame hands the next in a walk (LiSPSM's smoothed n, the culler's visibility, the trees\n"
                      "that counted in the shadow map, drawn first) (0 to 100)")
      ->check(CLI::Range(0, 100))
      ->capture_default_str();
  options->frame.add(*command);
  command->add_option("--bias", options->bias, "Slope-scale depth bias in the shadow pass (0 to 100; 0: none)")
      ->check(CLI::Range(0.0, 100.0))
      ->capture_default_str();
  command->add_flag("--front-faces", options->frontFaces, "Render front faces into the shadow map (not backside rendering)");
  command->add_option("--fog", options->fog,
                      "Distance haze: exponential extinction per metre, 0 to 1 (0: none; default: the scene's [render] haze)")
      ->check(CLI::Range(0.0, 1.0));
}

}  // namespace

Run addRenderCommand(CLI::App& app) {
  auto options = std::make_shared<RenderOptions>();
  CLI::App* command = app.add_subcommand(
      "render",
      "Render one frame of a scene (culling, shadows, lighting) to an image and a JSON record (headless;\n"
      "fields: docs/report-format.md)");
  addFrameInputs(command, options.get());
  command->add_option("--out", options->out, "Output image file (.png or .exr; its folder must exist)")
      ->required()
      ->check(CLI::Validator(
          [](std::string& file) -> std::string {
            const std::string extension = std::filesystem::path(file).extension().string();
            return extension == ".png" || extension == ".exr" ? std::string() : "expected a file name ending in .png or .exr, not " + file;
          },
          "", "image file"))
      ->check(outputFile());
  command->add_option("--json", options->json, "JSON record of the frame (default: the image path with .json)")->check(outputFile());
  command->add_option("--debug", options->debug,
                      "Folder for debug images: shadow map (EXR, and a PNG with its depth scale; with cascades one per\n"
                      "slice, shadow-map-<i>.*), shadow term before and after the blur, top-down.png (legend, view frustum,\n"
                      "focus body B, light frustum — per slice with cascades —, receivers, casters), cascades.png (the image\n"
                      "tinted by the slice each pixel reads)")
      ->check(outputFolder());
  return [options] { return runRender(*options); };
}

Run addTruthCommand(CLI::App& app) {
  auto options = std::make_shared<RenderOptions>();
  auto folder = std::make_shared<std::string>();
  CLI::App* command = app.add_subcommand(
      "truth",
      "Render one frame and measure it against a ray-traced truth of the same geometry (Embree): misclassified\n"
      "pixels near and away from shadow edges, false shadow and false light, the blurred term against a\n"
      "sun-disc soft truth, aliasing per pixel, casters selected against the casters the truth needs\n"
      "(fields: docs/report-format.md)");
  addFrameInputs(command, options.get());
  command->add_option("--out", *folder, "Folder for frame.png, frame.json, truth.json and error.png (false shadow\n"
                                        "red, false light blue, agreement grey; created when missing)")
      ->required()
      ->check(outputFolder());
  addSoftRaysOption(*command, options->softRays);
  return [options, folder] {
    RenderOptions o = *options;
    o.out = (std::filesystem::path(*folder) / "frame.png").string();
    o.truthFolder = *folder;
    return runRender(o);
  };
}

}  // namespace forest::app
