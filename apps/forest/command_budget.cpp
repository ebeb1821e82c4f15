// forest budget: a camera-path run (the walkthrough) checked against a frame-time budget
// (core/budget.hpp): each limit's statistic with its 95% interval over the run's frames and a
// verdict — holds, OVER, inconclusive, or a run too short to tell. Exit 0 when all hold, 1 when one
// is over (--report-only: 0), 3 when none is over but one could not be decided. A budget in
// reference frames is judged against the reference frame timed on this machine during the run,
// between its frames, under the same load (apps/forest/reference_frame.hpp).
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
#include "forest/gl/context.hpp"
#include "reference_frame.hpp"

namespace forest::app {
namespace {

constexpr int kInconclusiveExit = 3;

struct BudgetOptions {
  std::string budget;
  bool reportOnly = false;
  bool calibrate = false;
  WalkthroughOptions run;
};

// The reference frame's time on this machine, in a context of its own at the run's size.
double referenceFrameMs(const BudgetOptions& options) {
  gl::ContextOptions contextOptions;
  contextOptions.backend = gl::kBackendNames.parse(options.run.gl.backend);
  contextOptions.width = options.run.size.width;
  contextOptions.height = options.run.size.height;
  const auto context = gl::createContext(contextOptions);
  return measureReferenceFrameMs(options.run.size.width, options.run.size.height);
}

// The subject's milliseconds per measured frame (report.json's frames after the warm-up).
std::vector<double> seriesOf(const nlohmann::json& frames, const std::string& subject) {
  std::vector<double> series;
  for (const nlohmann::json& f : frames) {
    if (f.at("warmup").get<bool>()) continue;
    series.push_back(subject == "frame" ? f.at("frame_ms").get<double>() : f.at("passes_ms").at(subject).get<double>());
  }
  return series;
}

std::string verdictText(const LimitVerdict& v) {
  switch (v.verdict) {
    case Verdict::Holds: return "ok";
    case Verdict::Over: return "OVER";
    case Verdict::Inconclusive:
      return v.framesToDecide > 0 ? fmt::format("inconclusive (~{} frames would decide)", v.framesToDecide) : "inconclusive";
    case Verdict::TooShort: return fmt::format("too short (needs {} frames)", v.framesToDecide);
  }
  return {};
}

// Prints one line per limit; returns the verdicts.
std::vector<LimitVerdict> judgeRun(const Budget& budget, const nlohmann::json& frames, double referenceMs) {
  std::vector<LimitVerdict> verdicts;
  const bool relative = budget.unit == BudgetUnit::ReferenceFrames;
  std::cout << fmt::format("  {:<14} {:<5} {:>10} {:>10} {:>23}\n", "", "", relative ? "limit ref" : "", "limit ms",
                           "measured ms [95% int.]");
  for (const BudgetLimit& limit : budget.limits) {
    const std::vector<double> series = seriesOf(frames, limit.subject);
    const LimitVerdict v = judgeLimit(series, limit, budget.unit, referenceMs);
    verdicts.push_back(v);
    const std::string measured = v.verdict == Verdict::TooShort ? std::string("-")
                                                                 : fmt::format("{:.2f} [{:.2f}, {:.2f}]", v.measured.value,
                                                                               v.measured.low, v.measured.high);
    std::cout << fmt::format("  {:<14} {:<5} {:>10} {:>10.2f} {:>23}  {}\n", limit.subject, limit.statistic,
                             relative ? fmt::format("{:.3f}", limit.value) : std::string(), v.limitMs, measured, verdictText(v));
  }
  return verdicts;
}

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
  const bool relative = budget.unit == BudgetUnit::ReferenceFrames;
  if (options.calibrate) {
    const double ms = referenceFrameMs(options);
    std::cout << fmt::format("reference frame at {}x{}: {:.2f} ms on this machine\n", options.run.size.width, options.run.size.height, ms);
    for (const BudgetLimit& limit : budget.limits)
      std::cout << fmt::format("  {:<14} {:<5} {:>10.2f} ms\n", limit.subject, limit.statistic, relative ? limit.value * ms : limit.value);
    return 0;
  }
  options.run.every = kFirstFrameOnly;  // a budget run keeps no frames but the first
  options.run.length.quiet = true;
  // The machine's speed during the run, when the limits are in reference frames: the reference
  // frame timed between every 20th frame and the next, under whatever else the machine does then
  // (a reference timed only before and after missed a compile that came and went: the walk slowed
  // 2.9×, the reference 1.9×). The median of those times.
  std::vector<double> referenceTimes;
  std::unique_ptr<ReferenceFrame> reference;
  if (relative)
    options.run.betweenFrames = [&] {
      if (!reference) {
        reference = std::make_unique<ReferenceFrame>(options.run.size.width, options.run.size.height);
        (void)reference->timeOnceMs();  // the first draw compiles and allocates
      }
      referenceTimes.push_back(reference->timeOnceMs());
    };
  const int status = runWalkthrough(options.run);
  if (status != 0) return status;
  if (relative && referenceTimes.empty()) referenceTimes.push_back(referenceFrameMs(options));  // a run under 20 frames
  const double referenceMs = relative ? percentile(referenceTimes, 0.5) : 0.0;
  const nlohmann::json report = nlohmann::json::parse(readTextFile(std::filesystem::path(options.run.out) / "report.json"));
  std::cout << fmt::format("budget {} ({} frames measured{}):\n", shownPath(options.budget),
                           report.at("summary").at("frames_measured").get<int>(),
                           relative ? fmt::format("; reference frame {:.2f} ms on this machine, median of {} during the run",
                                                  referenceMs, referenceTimes.size())
                                    : "");
  if (!changed.empty())
    std::cout << fmt::format("  not the budget's run: {}; its limits were set for the budget's run\n", fmt::join(changed, ", "));
  const std::vector<LimitVerdict> verdicts = judgeRun(budget, report.at("frames"), referenceMs);
  int over = 0, undecided = 0;
  for (const LimitVerdict& v : verdicts) {
    over += v.verdict == Verdict::Over ? 1 : 0;
    undecided += v.verdict == Verdict::Inconclusive || v.verdict == Verdict::TooShort ? 1 : 0;
  }
  if (over > 0) {
    std::cout << fmt::format("{} of {} limits exceeded{}\n", over, verdicts.size(), options.reportOnly ? " (--report-only: exit 0)" : "");
    return options.reportOnly ? 0 : 1;
  }
  if (undecided > 0) {
    std::cout << fmt::format("{} of {} limits undecided: the run cannot tell (exit {})\n", undecided, verdicts.size(), kInconclusiveExit);
    return options.reportOnly ? 0 : kInconclusiveExit;
  }
  std::cout << fmt::format("all {} limits hold\n", verdicts.size());
  return 0;
}

}  // namespace

Run addBudgetCommand(CLI::App& app) {
  auto options = std::make_shared<BudgetOptions>();
  options->run.out = "out/budget";
  CLI::App* command = app.add_subcommand(
      "budget",
      "Run a camera path (as the walkthrough) and judge the p50/p95/p99/mean of the frame and of each pass against a "
      "budget file (data/budgets/*.toml; limits in ms or in reference frames timed on this machine): each with its 95% "
      "interval over the frames; OVER only when the interval lies above the limit, ok when at or below it, else "
      "inconclusive. Exit 0 all hold, 1 one is over, 3 one is undecided (inconclusive, or a run too short for its "
      "percentile). Writes the run's report.json (fields: docs/report-format.md)");
  options->run.size = {0, 0};  // the budget file's unless given
  options->run.add(*command, false);
  command->add_option("--budget", options->budget, "Budget file (TOML), e.g. data/budgets/walk-relative.toml")
      ->required()
      ->check(CLI::ExistingFile);
  command->add_flag("--report-only", options->reportOnly, "Print the table but exit 0 whatever the verdicts");
  command->add_flag("--calibrate", options->calibrate,
                    "Only time the reference frame at the run's size on this machine and print the budget's limits in ms");
  return [options] { return runBudget(*options); };
}

}  // namespace forest::app
