// forest budget: a camera-path run (the walkthrough) whose summary is checked against a frame-time
// budget (core/budget.hpp): a table of every limit with its measured value and margin; exit 0 when
// all hold, 1 otherwise (--report-only: always 0).
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "commands.hpp"
#include "forest/core/budget.hpp"
#include "forest/core/files.hpp"

namespace forest::app {
namespace {

struct BudgetOptions {
  std::string budget;
  bool reportOnly = false;
  WalkthroughOptions run;
};

int runBudget(BudgetOptions options) {
  const Budget budget = loadBudget(options.budget);  // bad files fail before anything renders
  // --width, --height, --frames shorten or resize the run (0: not given, the budget's own).
  std::vector<std::string> changed;
  auto take = [&](int& value, int budgetValue, const char* flag) {
    if (value == 0) value = budgetValue;
    else if (value != budgetValue) changed.push_back(fmt::format("{} {} (budget: {})", flag, value, budgetValue == 0 ? std::string("the whole path") : std::to_string(budgetValue)));
  };
  take(options.run.size.width, budget.width, "--width");
  take(options.run.size.height, budget.height, "--height");
  take(options.run.length.frames, budget.frames, "--frames");
  options.run.every = 1000000;  // a budget run keeps no frames but the first
  options.run.length.quiet = true;
  const int status = runWalkthrough(options.run);
  if (status != 0) return status;
  const nlohmann::json report = nlohmann::json::parse(readTextFile(std::filesystem::path(options.run.out) / "report.json"));
  const nlohmann::json& summary = report.at("summary");
  std::cout << fmt::format("budget {} ({} frames measured):\n  {:<14} {:<5} {:>10} {:>10} {:>9}\n", options.budget,
                           summary.at("frames_measured").get<int>(), "", "", "limit ms", "ms", "margin");
  if (!changed.empty())
    std::cout << fmt::format("  not the budget's run: {}; its limits were set for the budget's run\n", fmt::join(changed, ", "));
  int over = 0;
  for (const BudgetLimit& limit : budget.limits) {
    const nlohmann::json& stats = limit.subject == "frame" ? summary.at("frame_ms") : summary.at("passes_ms").at(limit.subject);
    const double measured = stats.at(limit.statistic).get<double>();
    const double margin = (limit.milliseconds - measured) / limit.milliseconds;
    const bool holds = measured <= limit.milliseconds;
    over += holds ? 0 : 1;
    std::cout << fmt::format("  {:<14} {:<5} {:>10.2f} {:>10.2f} {:>+8.1f}%  {}\n", limit.subject, limit.statistic, limit.milliseconds,
                             measured, 100.0 * margin, holds ? "ok" : "OVER");
  }
  std::cout << (over == 0 ? fmt::format("all {} limits hold\n", budget.limits.size())
                          : fmt::format("{} of {} limits exceeded{}\n", over, budget.limits.size(),
                                        options.reportOnly ? " (--report-only: exit 0)" : ""));
  return over == 0 || options.reportOnly ? 0 : 1;
}

}  // namespace

Run addBudgetCommand(CLI::App& app) {
  auto options = std::make_shared<BudgetOptions>();
  options->run.out = "out/budget";
  CLI::App* command = app.add_subcommand(
      "budget",
      "Run a camera path (as the walkthrough) and check the p50/p95/p99/mean of the frame and of each pass\n"
      "against a budget file (data/budgets/*.toml); prints every limit with its margin; exit 1 when one is exceeded.\n"
      "Writes the run's report.json (fields: docs/report-format.md)");
  options->run.size = {0, 0};  // the budget file's unless given
  options->run.add(*command, false);
  command->add_option("--budget", options->budget, "Budget file (TOML), e.g. data/budgets/llvmpipe-2core.toml")
      ->required()
      ->check(CLI::ExistingFile);
  command->add_flag("--report-only", options->reportOnly, "Print the table but exit 0 even when a limit is exceeded");
  return [options] { return runBudget(*options); };
}

}  // namespace forest::app
