// forest check: validates scene and camera-path files without rendering, and summarises them.
#include <fmt/format.h>

#include <iostream>

#include "commands.hpp"
#include "forest/core/camera_path.hpp"
#include "forest/core/error.hpp"
#include "forest/core/scene.hpp"

namespace forest::app {
namespace {

struct CheckOptions {
  std::string scene;
  std::string path;
};

int runCheck(const CheckOptions& options) {
  if (options.scene.empty() && options.path.empty()) throw InputError("check: give --scene FILE and/or --path FILE");
  if (!options.scene.empty()) {
    const Scene scene = loadScene(options.scene);
    std::cout << fmt::format("{}: ok — {}x{}, fovy {}°, near {}, far {}, {} props\n", options.scene,
                             scene.render.width, scene.render.height, scene.camera.fovy_deg, scene.camera.near,
                             scene.camera.far, scene.props.size());
  }
  if (!options.path.empty()) {
    const CameraPath path = CameraPath::load(options.path);
    std::cout << fmt::format("{}: ok — {} keys, t = {} … {} s\n", options.path, path.keys().size(),
                             path.startTime(), path.endTime());
  }
  return 0;
}

}  // namespace

Run addCheckCommand(CLI::App& app) {
  auto options = std::make_shared<CheckOptions>();
  CLI::App* command = app.add_subcommand("check", "Validate scene and camera-path files (no rendering)");
  command->add_option("--scene", options->scene, "Scene file (TOML)");
  command->add_option("--path", options->path, "Camera-path file (TOML)");
  return [options] { return runCheck(*options); };
}

}  // namespace forest::app
