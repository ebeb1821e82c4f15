// forest — command line of the forest engine. Errors print one line and exit non-zero:
// 2 for bad input (file, key, value), 1 for failures of the program or the machine.
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>

#include "commands.hpp"
#include "forest/core/error.hpp"
#include "forest/core/resources.hpp"

namespace forest::app {

void GlOptions::add(CLI::App& command) {
  command.add_option("--gl", backend,
                     "GL backend: auto (EGL, then OSMesa), egl (GPU device or Mesa surfaceless), "
                     "osmesa, window (GLFW; needs a display)")
      ->check(CLI::IsMember({"auto", "egl", "osmesa", "window"}))
      ->capture_default_str();
}

void FrameOptions::add(CLI::App& command) {
  command.add_option("--method", method, "Shadow method")
      ->check(CLI::IsMember(shadows::shadowMethodNames()))
      ->capture_default_str();
  command.add_option("--shadow-size", shadowSize, "Shadow map texels per side")->check(CLI::Range(512, 8192))->capture_default_str();
  command.add_option("--culling", culling, "Culling strategy")
      ->check(CLI::IsMember(culling::cullingStrategyNames()))
      ->capture_default_str();
  command.add_option("--pcf", pcf, "Wider PCF: (2r+1)² hardware 2×2 lookups (0: one)")->check(CLI::Range(0, 4))->capture_default_str();
  command.add_option("--blur", blur, "Eye-space blur of the shadow term: radius in pixels up to --blur-depth, then shrinking as 1/depth (0: off)")
      ->check(CLI::Range(0.0, 16.0))
      ->capture_default_str();
  command.add_option("--blur-depth", blurDepth, "Depth (m) up to which the blur has its full radius")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
}

render::FrameSettings FrameOptions::settings() const {
  render::FrameSettings s;
  s.method = shadows::parseShadowMethod(method);
  s.shadowMapSize = shadowSize;
  s.culling = culling::parseCullingStrategy(culling);
  s.pcfRadius = pcf;
  s.blurRadius = blur;
  s.blurReferenceDepth = blurDepth;
  return s;
}

double percentile(std::vector<double> values, double p) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const double position = p * static_cast<double>(values.size() - 1);
  const size_t below = static_cast<size_t>(position);
  const size_t above = std::min(below + 1, values.size() - 1);
  return values[below] + (values[above] - values[below]) * (position - static_cast<double>(below));
}

std::string sceneFileOr(const std::string& given) {
  return given.empty() ? (resourceDirectory("data") / "scenes" / "forest.toml").string() : given;
}

double residentMegabytes() {
  std::ifstream statm("/proc/self/statm");
  long pages = 0, resident = 0;
  statm >> pages >> resident;
  return static_cast<double>(resident) * static_cast<double>(sysconf(_SC_PAGESIZE)) / (1 << 20);
}

void showProgress(std::string_view what, std::string_view unit, int done, int total, double elapsed, bool quiet) {
  if (quiet) return;
  const double eta = done > 0 ? elapsed / done * (total - done) : 0.0;
  const int width = 30, filled = total > 0 ? width * done / total : width;
  const std::string bar = std::string(static_cast<size_t>(filled), '#') + std::string(static_cast<size_t>(width - filled), '.');
  if (isatty(STDERR_FILENO)) {
    std::cerr << fmt::format("\r[{}] {}/{} {}, {:.0f} s, ETA {:.0f} s ", bar, done, total, unit, elapsed, eta) << std::flush;
    if (done == total) std::cerr << "\n";
  } else if (done == total || done % std::max(1, total / 10) == 0) {
    std::cerr << fmt::format("{}: {}/{} {}, {:.0f} s, ETA {:.0f} s\n", what, done, total, unit, elapsed, eta);
  }
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
  add(forest::app::addTruthCommand);
  add(forest::app::addCheckCommand);
  add(forest::app::addStabilityCommand);
  add(forest::app::addBenchCommand);
  add(forest::app::addWalkthroughCommand);
  add(forest::app::addBudgetCommand);
  add(forest::app::addStressCommand);

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
