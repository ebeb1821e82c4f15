#pragma once
// The forest command line: every subcommand registered on one CLI11 app. Usage errors are one line
// "forest: error: <command>: <what>; see 'forest <command> --help'" and exit 2.
#include <CLI/CLI.hpp>

#include <string>
#include <utility>
#include <vector>

#include "commands.hpp"

namespace forest::app {

// The result of parsing alone: exitCode -1 when the arguments name a command ready to run; 0 for
// --help and --version (message: CLI11's text); 2 for a usage error (message: the one line).
struct CliParse {
  int exitCode = -1;
  std::string message;
};

class ForestCli {
 public:
  ForestCli();
  // Parses and runs the command; returns the process's exit code.
  int main(int argc, char** argv);
  // Parses only (arguments without the program name), for tests: nothing runs.
  CliParse parse(std::vector<std::string> arguments);
  // Runs the command the last parse chose; its errors print one line (exit 2 bad input, 1 failure).
  int run();
  CLI::App& app() { return app_; }

 private:
  CLI::App app_;
  std::vector<std::pair<CLI::App*, Run>> commands_;
};

}  // namespace forest::app
