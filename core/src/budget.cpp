#include "forest/core/budget.hpp"

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

}  // namespace forest
