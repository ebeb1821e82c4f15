#pragma once
// Frame-time budgets (forest budget): limits on percentiles of the whole frame and of each pass of a
// camera-path run, in milliseconds or in reference frames (a fixed GL workload timed on the machine
// the run is on: apps/forest/reference_frame.hpp). Files are TOML:
//   width = 1280          # optional run settings: image size, frames (0: the whole path)
//   height = 720
//   frames = 0
//   unit = "ms"           # or "reference": limits in multiples of the reference frame's time
//   [frame]               # any of p50, p95, p99, mean: in `unit`, > 0
//   p95 = 200.0
//   [passes.shadow]       # passes: geometry, shadow_setup, shadow, shadow_term, blur, lighting
//   p95 = 60.0
#include <filesystem>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "forest/core/enum_names.hpp"
#include "forest/core/statistics.hpp"

namespace forest {

enum class BudgetUnit { Milliseconds, ReferenceFrames };
inline constexpr EnumNames<BudgetUnit, 2> kBudgetUnitNames{
    "budget unit", {{{BudgetUnit::Milliseconds, "ms"}, {BudgetUnit::ReferenceFrames, "reference"}}}};

struct BudgetLimit {
  std::string subject;    // "frame" or a pass name
  std::string statistic;  // "mean", "p50", "p95", "p99"
  double value = 0.0;     // in the budget's unit
  Statistic measure() const;  // the statistic named
};

struct Budget {
  int width = 1280, height = 720;
  int frames = 0;  // 0: the whole path
  BudgetUnit unit = BudgetUnit::Milliseconds;
  std::vector<BudgetLimit> limits;  // in file order: frame first, then passes in the list above
};

// A limit against a run: the statistic over the run's measured frames with its 95% interval
// (bootstrapInterval), and the verdict — over when the whole interval lies above the limit, holds
// when it lies at or below it, inconclusive when it straddles the limit; too short when the run
// has fewer frames than the statistic needs (Statistic::framesNeeded: then nothing is estimated).
enum class Verdict { Holds, Over, Inconclusive, TooShort };
struct LimitVerdict {
  Verdict verdict = Verdict::TooShort;
  Interval measured;   // milliseconds
  double limitMs = 0;  // the limit in milliseconds (reference frames × the reference frame's time)
  // TooShort: the frames the statistic needs. Inconclusive: the frames that would likely decide it
  // (the interval's half-width shrinks as 1/√n: n·(half-width / distance to the limit)²); 0 when
  // the estimate sits on the limit.
  int framesToDecide = 0;
};
// `series`: the subject's milliseconds per measured frame, in frame order; `referenceMs`: the
// reference frame's time on this machine (used only with BudgetUnit::ReferenceFrames).
LimitVerdict judgeLimit(std::span<const double> series, const BudgetLimit& limit, BudgetUnit unit, double referenceMs);

// The passes a budget may name, in frame order.
const std::vector<std::string>& budgetPasses();

// Throws InputError naming the file, line and key: unknown pass or statistic, a number ≤ 0, ...
Budget parseBudget(const std::string& text, const std::string& name);
Budget loadBudget(const std::filesystem::path& file);

}  // namespace forest
