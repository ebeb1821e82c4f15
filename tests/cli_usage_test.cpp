// Every usage error of every subcommand is one line "forest: error: <command>: …" naming the flag,
// exit 2. The subcommands and options are read from the command line's own CLI11 app, so a flag
// added later is covered without touching this test; what must be refused comes from each option's
// declared type and range as --help prints it, and from outside the code (NaN and infinities are
// never valid): a non-finite number, a value past either end of the range, a name outside the
// choices, the option left out when it is required; and for each subcommand an unknown flag and a
// stray argument. Parsing runs in-process (ForestCli::parse, what main() runs first); a few cases
// go through the real program to check the exit code and stderr.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "cli.hpp"
#include "cli_test_support.hpp"
#include "test_paths.hpp"

namespace forest {
namespace {

using ::testing::HasSubstr;
using ::testing::StartsWith;

// One option as its type name declares it ("INT:INT in [16 - 8192]", "FLOAT x 5", "TEXT:{a,b}").
struct OptionSpec {
  std::string name;       // "--shadow-size"
  std::string type;       // INT, UINT, FLOAT, TEXT
  int count = 1;          // values per use
  bool hasRange = false;  // "in [low - high]"
  double low = 0.0, high = 0.0;
  bool choices = false;
  bool required = false;
  std::vector<std::string> needs;  // options it needs ("--script" needs "--window")
};

std::vector<OptionSpec> optionsOf(CLI::App& command) {
  std::vector<OptionSpec> options;
  const std::regex range(R"(in \[(\S+) - (\S+)\])");
  for (const CLI::Option* option : command.get_options()) {
    if (option->get_expected_max() == 0 || option->get_name(false, true).rfind("--", 0) != 0) continue;  // flags
    OptionSpec o;
    o.name = option->get_name(false, true);
    const std::string type = option->get_type_name();
    o.type = type.substr(0, type.find_first_of(":= "));
    std::smatch r;
    if (std::regex_search(type, r, range)) {
      o.hasRange = true;
      o.low = std::stod(r[1]);
      o.high = std::stod(r[2]);
    }
    o.count = std::max(1, option->get_expected_min());
    o.choices = type.find(":{") != std::string::npos;
    o.required = option->get_required();
    for (const CLI::Option* needed : option->get_needs()) o.needs.push_back(needed->get_name(false, true));
    options.push_back(o);
  }
  return options;
}

// Valid values for the required options, so each case fails only for the value under test.
std::vector<std::string> requiredArguments(const std::string& command, const std::string& leaveOut) {
  const std::map<std::string, std::vector<std::pair<std::string, std::string>>> required{
      {"render", {{"--out", "/tmp/never.png"}}},
      {"truth", {{"--out", "/tmp/never"}}},
      {"budget", {{"--budget", std::string(FOREST_REPO_DATA) + "/budgets/llvmpipe-2core.toml"}}}};
  std::vector<std::string> arguments;
  if (auto it = required.find(command); it != required.end())
    for (const auto& [flag, value] : it->second)
      if (flag != leaveOut) arguments.insert(arguments.end(), {flag, value});
  return arguments;
}

std::vector<std::string> words(const std::string& text) {
  std::istringstream in(text);
  std::vector<std::string> out;
  for (std::string w; in >> w;) out.push_back(w);
  return out;
}

// The usage-error contract, in-process: exit 2 and one line starting with `start`, naming `mentioned`.
void expectUsageError(const std::vector<std::string>& arguments, const std::string& start, const std::string& mentioned) {
  std::string shown;
  for (const std::string& a : arguments) shown += " " + a;
  SCOPED_TRACE("forest" + shown);
  app::ForestCli cli;
  const app::CliParse r = cli.parse(arguments);
  EXPECT_EQ(r.exitCode, 2) << r.message;
  EXPECT_THAT(r.message, StartsWith(start));
  EXPECT_THAT(r.message, HasSubstr(mentioned));
  EXPECT_EQ(r.message.find('\n'), std::string::npos) << r.message;
}

std::string number(double v) {
  std::ostringstream s;
  s.precision(17);
  s << v;
  return s.str();
}

// Every command that runs ("bench culling", not "bench"), by the name typed.
std::vector<std::pair<std::string, CLI::App*>> runnableCommands(app::ForestCli& cli) {
  std::vector<std::pair<std::string, CLI::App*>> commands;
  for (CLI::App* command : cli.app().get_subcommands({})) {
    const std::vector<CLI::App*> nested = command->get_subcommands({});
    if (nested.empty()) commands.emplace_back(command->get_name(), command);
    for (CLI::App* sub : nested) commands.emplace_back(command->get_name() + " " + sub->get_name(), sub);
  }
  return commands;
}

TEST(ForestCliUsage, EveryUsageErrorOfEverySubcommandIsOneLineWithExitTwo) {
  app::ForestCli cli;
  const std::vector<std::pair<std::string, CLI::App*>> commands = runnableCommands(cli);
  // A command that needs a subcommand, called without one.
  for (CLI::App* command : cli.app().get_subcommands({}))
    if (!command->get_subcommands({}).empty())
      expectUsageError({command->get_name()}, "forest: error: " + command->get_name() + ": ", "a command is required");
  std::vector<std::string> names;
  for (const auto& [name, command] : commands) names.push_back(name);
  // The commands the README documents; finding fewer means this test lost them, not the program.
  for (const char* expected : {"info", "render", "truth", "check", "stability", "bench culling", "bench speed-error", "walkthrough",
                               "budget", "stress"})
    EXPECT_THAT(names, ::testing::Contains(std::string(expected)));

  std::map<std::string, int> casesPerCommand;
  for (const auto& [name, command] : commands) {
    const std::string prefix = "forest: error: " + name + ": ";
    auto call = [&](const std::vector<std::string>& extra, const std::string& leaveOut = "") {
      std::vector<std::string> arguments = words(name);
      for (const std::string& a : requiredArguments(name, leaveOut)) arguments.push_back(a);
      arguments.insert(arguments.end(), extra.begin(), extra.end());
      return arguments;
    };
    expectUsageError(call({"--no-such-flag"}), prefix, "unknown option '--no-such-flag'");
    expectUsageError(call({"stray"}), prefix, "unexpected argument 'stray'");
    casesPerCommand[name] += 2;
    for (const OptionSpec& o : optionsOf(*command)) {
      auto with = [&](const std::string& value) {
        std::vector<std::string> extra = o.needs;
        extra.push_back(o.name);
        for (int i = 0; i < o.count; ++i) extra.push_back(value);
        return call(extra);
      };
      std::vector<std::string> refused;
      if (o.type == "INT" || o.type == "UINT" || o.type == "FLOAT") refused = {"nan", "inf", "-inf", "1e999"};
      if (o.hasRange) {
        // Past either end: the next integer, or a step of the range's width (at least 1) for reals.
        const double step = o.type == "FLOAT" ? std::max(1.0, o.high - o.low) : 1.0;
        refused.push_back(number(o.high + step));
        if (o.low - step >= 0.0 || o.type != "UINT") refused.push_back(number(o.low - step));
      }
      if (o.choices) refused.push_back("no-such-choice");
      for (const std::string& value : refused) expectUsageError(with(value), prefix, o.name);
      casesPerCommand[name] += static_cast<int>(refused.size());
      if (o.required) {
        expectUsageError(call({}, o.name), prefix, o.name + " is required");
        ++casesPerCommand[name];
      }
    }
  }
  // Each rendering command has its size, frame and shadow flags: at least 4 refused values for each
  // of --width, --height, --shadow-size, --pcf, --blur, --blur-depth. Fewer means the options were
  // not seen.
  for (const char* command : {"render", "truth", "walkthrough", "budget", "stress"}) EXPECT_GE(casesPerCommand[command], 36) << command;
}

// Every option's range as the README and each --help document it: written here, so that a range
// changed in the code (or its help text) without the documentation fails.
struct DocumentedRange {
  const char* option;
  double low, high;
};
constexpr DocumentedRange kDocumentedRanges[] = {
    {"--width", 16, 8192},       {"--height", 16, 8192},        {"--shadow-size", 512, 8192}, {"--sizes", 512, 8192},
    {"--pcf", 0, 4},             {"--blur", 0, 16},             {"--blur-depth", 0.01, 1e4},  {"--bias", 0, 100},
    {"--cascades", 1, 4},        {"--split-lambda", 0, 1},      {"--cascade-blend", 0, 0.5},  {"--fog", 0, 1},
    {"--time", 0, 1e6},          {"--frames", 1, 1e6},          {"--warmup", 0, 1e6},         {"--every", 1, 1e6},
    {"--check-every", 0, 1e6},   {"--fps", 0.1, 1000},          {"--trees", 1, 1e6},          {"--leaf-size", 1, 64},
    {"--moving", 0, 1},          {"--soft-rays", 0, 1024},      {"--screen", 1, 16384},       {"--random", 0, 1e8},
    {"--target", 1e-6, 0.999999}, {"--lod0", 1000, 20000},   {"--views", 2, 1000},         {"--rounds", 1, 100},
    {"--frames-before", 0, 100}, {"--far-slice-scale", 0.5, 2}, {"--repeats", 1, 100},
    {"--dolly-frames", 2, 1000},  {"--dolly-step", 0.01, 100},
};

TEST(ForestCliUsage, EveryRangedOptionHasItsDocumentedRangeAndAcceptsItsEnds) {
  app::ForestCli cli;
  const std::vector<std::pair<std::string, CLI::App*>> commands = runnableCommands(cli);
  int checked = 0;
  for (const auto& [name, command] : commands)
    for (const OptionSpec& o : optionsOf(*command)) {
      if (!o.hasRange) continue;
      SCOPED_TRACE(name + " " + o.name);
      const auto documented = std::find_if(std::begin(kDocumentedRanges), std::end(kDocumentedRanges),
                                            [&](const DocumentedRange& d) { return o.name == d.option; });
      ASSERT_NE(documented, std::end(kDocumentedRanges)) << "a ranged option without a documented range";
      EXPECT_DOUBLE_EQ(o.low, documented->low);
      EXPECT_DOUBLE_EQ(o.high, documented->high);
      // Its help says so in words too: "low to high".
      const std::string help = command->get_option(o.name)->get_description();
      // Numbers as the help writes them: 0.01, 1e-06, 8192, and 1000000 or 10^6.
      auto written = [](double v) {
        std::vector<std::string> forms{v == std::floor(v) ? fmt::format("{:.0f}", v) : fmt::format("{:g}", v)};
        const double power = std::round(std::log10(v));
        if (v >= 1e3 && v == std::pow(10.0, power)) forms.push_back(fmt::format("10^{:.0f}", power));
        return forms;
      };
      bool said = false;
      for (const std::string& low : written(documented->low))
        for (const std::string& high : written(documented->high)) said = said || help.find(low + " to " + high) != std::string::npos;
      EXPECT_TRUE(said) << "the help does not give the range: " << help;
      // Both ends are valid values.
      for (double end : {documented->low, documented->high}) {
        std::vector<std::string> arguments = words(name);
        for (const std::string& a : requiredArguments(name, "")) arguments.push_back(a);
        for (const std::string& n : o.needs) arguments.push_back(n);
        arguments.push_back(o.name);
        for (int i = 0; i < o.count; ++i) arguments.push_back(number(end));
        app::ForestCli fresh;
        const app::CliParse r = fresh.parse(arguments);
        EXPECT_EQ(r.exitCode, -1) << number(end) << ": " << r.message;
      }
      ++checked;
    }
  EXPECT_GE(checked, 60);  // the options were seen (80 ranged options in 9 commands)
}

// Through the real program: stderr, exit code, nothing on stdout.
void expectProgramUsageError(const std::string& arguments, const std::string& start, const std::string& mentioned) {
  SCOPED_TRACE("forest " + arguments);
  const test::CliResult r = test::runForest(arguments);
  EXPECT_EQ(r.exitCode, 2) << r.err;
  EXPECT_THAT(r.err, StartsWith(start));
  EXPECT_THAT(r.err, HasSubstr(mentioned));
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_EQ(r.out, "");
}

TEST(ForestCliUsage, UnknownCommandAndNoCommandNameTheChoices) {
  expectProgramUsageError("frobnicate", "forest: error: ", "unknown command 'frobnicate' (one of: info, render");
  expectProgramUsageError("", "forest: error: ", "a command is required (one of: info, render");
}

TEST(ForestCliUsage, ExtraArgumentsAreNamedInTheOrderGiven) {
  // CLI11 itself lists them reversed ("20 --frames"); the message must read as typed.
  expectProgramUsageError("info stray 20", "forest: error: info: ", "unexpected arguments 'stray 20'");
}

TEST(ForestCliUsage, AMisspelledOptionGetsTheNearestOneAndACountMismatchSaysTheCount) {
  expectProgramUsageError("render --shadow-szie 1024 --out /tmp/never.png", "forest: error: render: ",
                          "unknown option '--shadow-szie' (did you mean '--shadow-size'?)");
  expectProgramUsageError("render --frobnicate 1 --out /tmp/never.png", "forest: error: render: ", "unknown option '--frobnicate';");
  expectProgramUsageError("render --camera 1 2 3 4 5 6 --out /tmp/never.png", "forest: error: render: ",
                          "--camera: expected 5 values, got 6");
}

// Every help page fits 100 columns and says each range once (in words: "16 to 8192"; CLI11's
// "INT:INT in [16 - 8192]" is not printed); the top-level help names the bench subcommands.
TEST(ForestCliUsage, HelpPagesFitOneHundredColumnsAndSayEachRangeOnce) {
  app::ForestCli cli;
  std::vector<std::string> pages{""};
  for (const auto& [name, command] : runnableCommands(cli)) pages.push_back(name);
  pages.push_back("bench");
  for (const std::string& page : pages) {
    const test::CliResult r = test::runForest(page + " --help");
    SCOPED_TRACE("forest " + page + " --help");
    EXPECT_EQ(r.exitCode, 0);
    std::istringstream lines(r.out);
    for (std::string line; std::getline(lines, line);) {
      // Columns, not bytes: UTF-8 continuation bytes take none.
      const auto columns = std::count_if(line.begin(), line.end(), [](char c) { return (static_cast<unsigned char>(c) & 0xC0) != 0x80; });
      EXPECT_LE(columns, 100) << line;
      EXPECT_EQ(line.find(" in ["), std::string::npos) << line;
    }
  }
  EXPECT_THAT(test::runForest("--help").out, HasSubstr("(culling, speed-error, passes, scale, impostors)"));
}

TEST(ForestCliUsage, RuntimeInputErrorsKeepTheFormat) {
  // Checked after parsing, still one line and exit 2.
  expectProgramUsageError("render --camera 0 2 0 0 95 --out /tmp/never.png", "forest: error: ", "--camera: pitch 95: expected -90 to 90 degrees");
  expectProgramUsageError("walkthrough --frames 4 --warmup 4 --out /tmp/never", "forest: error: ", "--warmup 4: expected fewer than the 4 frames");
}

// The commit is a hash in a git checkout and says it is unknown in a source archive (no .git:
// a release tarball, a distribution's build).
TEST(ForestCliUsage, VersionNamesVersionCommitAndBackends) {
  const test::CliResult r = test::runForest("--version");
  EXPECT_EQ(r.exitCode, 0) << r.err;
  const bool checkout = std::filesystem::exists(std::filesystem::path(test::repoDataDir()).parent_path() / ".git");
  const std::string commit = checkout ? "[0-9a-f]{7,}(-dirty)?" : "unknown \\(not built from a git checkout\\)";
  EXPECT_TRUE(std::regex_match(r.out, std::regex("forest [0-9]+\\.[0-9]+\\.[0-9]+ \\(commit " + commit + "\\)\n"
                                                 "GL backends built in: egl [^\n]*osmesa [^\n]*window [^\n]*\n")))
      << r.out << "(a git checkout: " << checkout << ")";
}

}  // namespace
}  // namespace forest
