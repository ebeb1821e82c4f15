// forest render: one lit frame of a scene, written as a PNG (headless by default).
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <iostream>

#include "commands.hpp"
#include "forest/core/error.hpp"
#include "forest/core/image.hpp"
#include "forest/core/log.hpp"
#include "forest/core/resources.hpp"
#include "forest/core/scene.hpp"
#include "forest/gl/context.hpp"
#include "forest/gl/debug.hpp"
#include "forest/render/offscreen_target.hpp"
#include "forest/render/scene_view.hpp"

namespace forest::app {
namespace {

struct RenderOptions {
  GlOptions gl;
  std::string scene;
  std::string out;
  int width = 0;
  int height = 0;
  double time = 0.0;
};

int runRender(const RenderOptions& options) {
  const std::string scenePath =
      options.scene.empty() ? (resourceDirectory("data") / "scenes" / "boxes.toml").string() : options.scene;
  Scene scene = loadScene(scenePath);
  if (options.width > 0) scene.render.width = options.width;
  if (options.height > 0) scene.render.height = options.height;

  gl::ContextOptions contextOptions;
  contextOptions.backend = gl::parseBackend(options.gl.backend);
  contextOptions.width = scene.render.width;
  contextOptions.height = scene.render.height;
  auto context = gl::createContext(contextOptions);
  log::info("{}", gl::describe(context->info()));

  render::OffscreenTarget target(scene.render.width, scene.render.height);
  const render::SceneView view(scene);
  target.bind();
  const render::SceneView::Stats stats = view.draw(view.startCamera(), scene.render.height, options.time);
  const Image8 image = target.readColor();
  if (gl::debugErrorCount() > 0) {
    throw Error(fmt::format("{} GL errors while rendering (first: {})", gl::debugErrorCount(),
                            gl::debugErrorMessages().front()));
  }
  writeImage(options.out, image);
  std::cout << fmt::format("wrote {} ({}x{}, {} props, {} prop triangles", options.out, image.width, image.height,
                           scene.props.size(), stats.propTriangles);
  if (view.terrain()) {
    std::cout << fmt::format(", terrain {} tiles (per level {}), {} triangles, {:.1f} MiB on the GPU",
                             stats.terrain.tiles, fmt::join(stats.terrain.tilesPerLevel, "/"), stats.terrain.triangles,
                             static_cast<double>(view.terrain()->gpuBytes()) / (1 << 20));
  }
  if (view.forest()) {
    std::cout << fmt::format(", {} of {} trees drawn (per LOD {}), {} tree triangles in {} draws", stats.trees.trees,
                             view.forest()->trees().size(), fmt::join(stats.trees.treesPerLod, "/"),
                             stats.trees.triangles, stats.trees.draws);
  }
  std::cout << fmt::format(") from {}\n", scenePath);
  return 0;
}

}  // namespace

Run addRenderCommand(CLI::App& app) {
  auto options = std::make_shared<RenderOptions>();
  CLI::App* command = app.add_subcommand("render", "Render one lit frame of a scene to an image (headless)");
  options->gl.add(*command);
  command->add_option("--scene", options->scene, "Scene file (TOML; default: data/scenes/boxes.toml)");
  command->add_option("--out", options->out, "Output image (.png 8-bit, .exr float)")->required();
  command->add_option("--width", options->width, "Override render.width")->check(CLI::Range(1, 16384));
  command->add_option("--height", options->height, "Override render.height")->check(CLI::Range(1, 16384));
  command->add_option("--time", options->time, "Seconds since the start (wind sway)")->capture_default_str();
  return [options] { return runRender(*options); };
}

}  // namespace forest::app
