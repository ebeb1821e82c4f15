// The forest command line as an object: every subcommand registered, the arguments parsed
// (usage errors as one line, exit 2), the chosen command run (its errors as one line, exit 2 for
// bad input, 1 for failures of the program or the machine). main() and the tests share it.
#include "cli.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstddef>
#include <cstdio>
#include <fstream>
#include <iostream>

#include "build_info.hpp"
#include "commands.hpp"
#include "help_format.hpp"
#include "forest/core/error.hpp"
#include "forest/core/resources.hpp"
#include "forest/core/suggest.hpp"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

namespace forest::app {

std::string sceneFileOr(const std::string& given) {
  return given.empty() ? (resourceDirectory("data") / "scenes" / "forest.toml").string() : given;
}

std::string shownPath(const std::filesystem::path& path) {
  std::error_code ec;
  const std::filesystem::path absolute = std::filesystem::absolute(path, ec), here = std::filesystem::current_path(ec);
  if (ec) return path.string();
  const std::filesystem::path relative = absolute.lexically_normal().lexically_relative(here);
  const bool inside = !relative.empty() && *relative.begin() != "..";
  return inside ? relative.string() : absolute.lexically_normal().string();
}

std::string walkPathOr(const std::string& given) {
  return given.empty() ? (resourceDirectory("data") / "paths" / "walk.toml").string() : given;
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


namespace forest::app {
namespace {

// The deepest command the arguments named ("forest", "forest bench", "forest bench culling").
CLI::App* namedCommand(CLI::App& app) {
  for (CLI::App* sub : app.get_subcommands({}))
    if (sub->parsed()) return namedCommand(*sub);
  return &app;
}

std::string commandPath(const CLI::App* command) {
  std::string path = command->get_name();
  for (const CLI::App* p = command->get_parent(); p != nullptr; p = p->get_parent()) path = p->get_name() + " " + path;
  return path;
}

// Arguments left over: an unknown option (with the nearest known one, if it looks like a typo of
// it), or values no option takes — named in the order given (CLI11 lists them reversed).
std::string unexpectedArguments(const CLI::App& command) {
  const std::vector<std::string> given = command.remaining();
  const auto isFlag = [](const std::string& a) { return a.size() > 1 && a[0] == '-' && !std::isdigit(static_cast<unsigned char>(a[1])) && a[1] != '.'; };
  const auto unknown = std::find_if(given.begin(), given.end(), isFlag);
  if (unknown == given.end()) return fmt::format("unexpected argument{} '{}'", given.size() > 1 ? "s" : "", fmt::join(given, " "));
  const std::string name = unknown->substr(0, unknown->find('='));
  std::vector<std::string> known;
  for (const CLI::Option* option : command.get_options())
    for (const std::string& l : option->get_lnames()) known.push_back("--" + l);
  const std::string nearest = nearestName(name, known);
  return fmt::format("unknown option '{}'{}", name, nearest.empty() ? "" : fmt::format(" (did you mean '{}'?)", nearest));
}

// CLI11's "--camera: At Most 5 required but received 6" as "--camera: expected 5 values, got 6".
std::string valueCountMismatch(const CLI::App& command, const std::string& message) {
  const std::string name = message.substr(0, message.find(':'));
  const std::string received = message.substr(message.find_last_of(' ') + 1);
  const CLI::Option* option = nullptr;
  try {
    option = command.get_option(name);
  } catch (const CLI::OptionNotFound&) {
    return message;
  }
  const int low = option->get_expected_min(), high = option->get_expected_max();
  const std::string expected = low == high ? fmt::format("{}", low) : fmt::format("{} to {}", low, high);
  return fmt::format("{}: expected {} value{}, got {}", name, expected, high == 1 ? "" : "s", received);
}

// A usage error as one line: "forest: error: render: --shadow-size: …; see 'forest render --help'".
std::string usageError(CLI::App& app, const CLI::ParseError& e) {
  CLI::App* command = namedCommand(app);
  const std::string path = commandPath(command);
  std::string what = e.what();
  const std::vector<CLI::App*> subs = command->get_subcommands({});
  if (dynamic_cast<const CLI::RequiredError*>(&e) != nullptr && !subs.empty() && command->get_subcommands().empty()) {
    // No (known) subcommand: name the one given, if any, and list the choices.
    std::vector<std::string> names;
    for (const CLI::App* sub : subs) names.push_back(sub->get_name());
    const std::vector<std::string> given = command->remaining();
    what = (given.empty() ? std::string("a command is required") : fmt::format("unknown command '{}'", given.front())) +
           fmt::format(" (one of: {})", fmt::join(names, ", "));
  } else if (dynamic_cast<const CLI::ExtrasError*>(&e) != nullptr && !command->remaining().empty()) {
    what = unexpectedArguments(*command);
  } else if (dynamic_cast<const CLI::ArgumentMismatch*>(&e) != nullptr) {
    what = valueCountMismatch(*command, what);
  }
  std::replace(what.begin(), what.end(), '\n', ' ');
  const std::string prefix = command == &app ? std::string() : path.substr(path.find(' ') + 1) + ": ";
  return fmt::format("forest: error: {}{}; see '{} --help'", prefix, what, path);
}

std::string versionText() {
  int major = 0, minor = 0, revision = 0;
  glfwGetVersion(&major, &minor, &revision);
  return fmt::format(
      "forest {} (commit {})\n"
      "GL backends built in: egl (EGL device or Mesa surfaceless), osmesa (libOSMesa, loaded at run time), "
      "window (GLFW {}.{}.{})",
      FOREST_VERSION, FOREST_COMMIT, major, minor, revision);
}

}  // namespace


ForestCli::ForestCli()
    : app_("forest — large outdoor scenes: procedural terrain and trees, exact occlusion culling (CHC),\n"
           "light space perspective shadow maps. Run 'forest <command> --help' for each command.\n\n"
           "Output files (report.json, frame.json, truth.json, ...): docs/report-format.md.\n\n"
           "Exit codes: 0 done, 1 a failure of the program or the machine (or a check that failed),\n"
           "2 bad input (a usage error, a bad file, key or value; one line 'forest: error: ...'), 130 interrupted.",
           "forest") {
  app_.formatter(std::make_shared<HelpFormatter>());  // before the subcommands: they take their parent's
  app_.require_subcommand(1);
  app_.set_version_flag("--version", versionText(), "Print the version, the commit and the GL backends built in");
  for (Run (*factory)(CLI::App&) : {addInfoCommand, addRenderCommand, addTruthCommand, addCheckCommand, addStabilityCommand,
                                    addBenchCommand, addWalkthroughCommand, addBudgetCommand, addStressCommand}) {
    const size_t before = app_.get_subcommands({}).size();
    Run run = factory(app_);
    commands_.emplace_back(app_.get_subcommands({})[before], std::move(run));
  }
  requireFiniteNumbers(app_);
}

CliParse ForestCli::parse(std::vector<std::string> arguments) {
  std::reverse(arguments.begin(), arguments.end());  // CLI11 takes them last first
  try {
    app_.parse(std::move(arguments));
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return {0, e.what()};  // --help, --version
    return {2, usageError(app_, e)};
  }
  return {};
}

int ForestCli::main(int argc, char** argv) {
  try {
    app_.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app_.exit(e);  // --help, --version
    std::fprintf(stderr, "%s\n", usageError(app_, e).c_str());
    return 2;
  }
  return run();
}

int ForestCli::run() {
  try {
    for (auto& [command, run] : commands_) {
      if (command->parsed()) return run();
    }
    return 2;
  } catch (const InputError& e) {
    std::fprintf(stderr, "forest: error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "forest: error: %s\n", e.what());
    return 1;
  }
}

}  // namespace forest::app
