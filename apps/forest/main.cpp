// forest — command line of the forest engine. Errors print one line and exit non-zero:
// 2 for bad input (file, key, value), 1 for failures of the program or the machine.
#include <cstdio>
#include <map>

#include "commands.hpp"
#include "forest/core/error.hpp"

namespace forest::app {

void GlOptions::add(CLI::App& command) {
  command.add_option("--gl", backend,
                     "GL backend: auto (EGL, then OSMesa), egl (GPU device or Mesa surfaceless), "
                     "osmesa, window (GLFW; needs a display)")
      ->check(CLI::IsMember({"auto", "egl", "osmesa", "window"}))
      ->capture_default_str();
}

}  // namespace forest::app

int main(int argc, char** argv) {
  CLI::App app{
      "forest — large outdoor scenes: procedural terrain and trees, exact occlusion culling (CHC),\n"
      "light space perspective shadow maps. Run 'forest <command> --help' for each command."};
  app.require_subcommand(1);
  std::map<CLI::App*, forest::app::Run> commands;
  auto add = [&](forest::app::Run (*factory)(CLI::App&)) {
    const size_t before = app.get_subcommands({}).size();
    forest::app::Run run = factory(app);
    commands[app.get_subcommands({})[before]] = std::move(run);
  };
  add(forest::app::addInfoCommand);
  add(forest::app::addRenderCommand);
  add(forest::app::addCheckCommand);
  add(forest::app::addStabilityCommand);
  add(forest::app::addBenchCommand);
  add(forest::app::addWalkthroughCommand);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  try {
    for (auto& [command, run] : commands) {
      if (command->parsed()) return run();
    }
    return 2;
  } catch (const forest::InputError& e) {
    std::fprintf(stderr, "forest: error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "forest: error: %s\n", e.what());
    return 1;
  }
}
