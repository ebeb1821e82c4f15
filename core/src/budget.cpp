#include "forest/core/budget.hpp"

#include <algorithm>
#include <cmath>

#include "forest/core/files.hpp"
#include "forest/core/frame_passes.hpp"
#include "toml_schema.hpp"

namespace forest {
namespace {

using detail::TomlSection;

const std::vector<std::string> kStatistics{"mean", "p50", "p95", "p99"};

void readLimits(TomlSection& section, const std::string& subject, Budget& budget) {
  for (const std::string& statistic : kStatistics)
    if (section.has(statistic))
      budget.limits.push_back({subject, statistic, section.number(statistic, std::nullopt, detail::positive())});
  section.finish();  // an unknown statistic is named with its line
}

}  // namespace

const std::vector<std::string>& budgetPasses() {
  static const std::vector<std::string> passes = kFramePassNames.names();
  return passes;
}

Budget parseBudget(const std::string& text, const std::string& name) {
  const toml::table document = detail::parseToml(text, name);
  TomlSection root(document, name, "");
  Budget b;
  b.width = static_cast<int>(root.integer("width", b.width, 16, 8192));
  b.height = static_cast<int>(root.integer("height", b.height, 16, 8192));
  b.frames = static_cast<int>(root.integer("frames", b.frames, 0, 1000000));
  b.unit = kBudgetUnitNames.parse(root.oneOf("unit", std::string("ms"), kBudgetUnitNames.names()));
  if (auto frame = root.table("frame")) readLimits(*frame, "frame", b);
  if (auto passes = root.table("passes")) {
    for (const std::string& pass : budgetPasses())
      if (auto section = passes->table(pass)) readLimits(*section, pass, b);
    passes->finish();  // an unknown pass is named with its line
  }
  root.finish();
  if (b.limits.empty()) root.fail(nullptr, "frame", "a budget needs at least one limit ([frame] or [passes.NAME])");
  return b;
}

Budget loadBudget(const std::filesystem::path& file) { return parseBudget(readTextFile(file), file.string()); }

Statistic BudgetLimit::measure() const {
  if (statistic == "mean") return {true, 0.0};
  return {false, std::stod(statistic.substr(1)) / 100.0};  // "p95" → 0.95 (parseBudget admits only kStatistics)
}

LimitVerdict judgeLimit(std::span<const double> series, const BudgetLimit& limit, BudgetUnit unit, double referenceMs) {
  LimitVerdict v;
  v.limitMs = unit == BudgetUnit::ReferenceFrames ? limit.value * referenceMs : limit.value;
  const Statistic statistic = limit.measure();
  const int n = static_cast<int>(series.size());
  if (n < statistic.framesNeeded()) {
    v.verdict = Verdict::TooShort;
    v.framesToDecide = statistic.framesNeeded();
    return v;
  }
  v.measured = bootstrapInterval(series, statistic);
  if (v.measured.low > v.limitMs) {
    v.verdict = Verdict::Over;
  } else if (v.measured.high <= v.limitMs) {
    v.verdict = Verdict::Holds;
  } else {
    v.verdict = Verdict::Inconclusive;
    const double halfWidth = 0.5 * (v.measured.high - v.measured.low), distance = std::abs(v.measured.value - v.limitMs);
    if (distance > 0.0) {
      const double frames = std::ceil(n * (halfWidth / distance) * (halfWidth / distance));
      v.framesToDecide = static_cast<int>(std::min(frames, 1e9));
    }
  }
  return v;
}

}  // namespace forest
