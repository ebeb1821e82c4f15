#pragma once
// Frame-time budgets (forest budget): limits in milliseconds on percentiles of the whole frame and
// of each pass of a camera-path run. Files are TOML:
//   width = 1280          # optional run settings: image size, frames (0: the whole path)
//   height = 720
//   frames = 0
//   [frame]               # any of p50, p95, p99, mean: milliseconds, > 0
//   p95 = 200.0
//   [passes.shadow]       # passes: geometry, shadow_setup, shadow, shadow_term, blur, lighting
//   p95 = 60.0
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace forest {

struct BudgetLimit {
  std::string subject;    // "frame" or a pass name
  std::string statistic;  // "mean", "p50", "p95", "p99"
  double milliseconds = 0.0;
};

struct Budget {
  int width = 1280, height = 720;
  int frames = 0;  // 0: the whole path
  std::vector<BudgetLimit> limits;  // in file order: frame first, then passes in the list above
};

// The passes a budget may name, in frame order.
const std::vector<std::string>& budgetPasses();

// Throws InputError naming the file, line and key: unknown pass or statistic, a number ≤ 0, ...
Budget parseBudget(const std::string& text, const std::string& name);
Budget loadBudget(const std::filesystem::path& file);

}  // namespace forest
