#pragma once
// Subcommands of the `forest` program. Each registers its options on the CLI and returns the
// function that runs it (exit code).
#include <CLI/CLI.hpp>

#include <functional>
#include <string>

namespace forest::app {

using Run = std::function<int()>;

// Options every GL-using subcommand has.
struct GlOptions {
  std::string backend = "auto";
  void add(CLI::App& command);
};

Run addInfoCommand(CLI::App& app);
Run addRenderCommand(CLI::App& app);
Run addCheckCommand(CLI::App& app);
Run addStabilityCommand(CLI::App& app);
Run addBenchCommand(CLI::App& app);
Run addWalkthroughCommand(CLI::App& app);

}  // namespace forest::app
