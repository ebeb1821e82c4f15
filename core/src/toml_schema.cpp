#include "toml_schema.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "forest/core/error.hpp"
#include "forest/core/suggest.hpp"
#include "forest/core/files.hpp"

namespace forest::detail {
namespace {

std::string location(const std::string& file, const toml::source_region& source) {
  if (source.begin.line == 0) return file;
  return fmt::format("{}:{}:{}", file, source.begin.line, source.begin.column);
}

// The value as one short line (arrays inline: "[ 0.0, nan, 0.0 ]").
std::string render(const toml::node& node) {
  std::string text;
  if (const toml::array* array = node.as_array()) {
    text = "[ ";
    for (size_t i = 0; i < array->size(); ++i) text += (i ? ", " : "") + render(*array->get(i));
    text += " ]";
  } else if (node.is_table()) {
    text = "{ ... }";
  } else {
    std::ostringstream out;
    node.visit([&](const auto& n) { out << n; });
    text = out.str();
  }
  std::replace(text.begin(), text.end(), '\n', ' ');
  if (text.size() > 60) text = text.substr(0, 57) + "...";
  return text;
}

}  // namespace

bool NumberRange::contains(double v) const {
  if (!std::isfinite(v)) return false;
  if (minOpen ? !(v > min) : !(v >= min)) return false;
  if (maxOpen ? !(v < max) : !(v <= max)) return false;
  return true;
}

std::string NumberRange::describe() const {
  const bool noMin = min <= -1e300;
  const bool noMax = max >= 1e300;
  if (noMin && noMax) return "a finite number";
  if (noMax) return fmt::format("a finite number {} {}", minOpen ? ">" : ">=", min);
  if (noMin) return fmt::format("a finite number {} {}", maxOpen ? "<" : "<=", max);
  return fmt::format("a number in {}{}, {}{}", minOpen ? "(" : "[", min, max, maxOpen ? ")" : "]");
}

NumberRange anyFinite() { return {}; }
NumberRange positive() { return {0.0, 1e300, true, false}; }
NumberRange nonNegative() { return {0.0, 1e300, false, false}; }
NumberRange closed(double min, double max) { return {min, max, false, false}; }
NumberRange open(double min, double max) { return {min, max, true, true}; }

TomlSection::TomlSection(const toml::table& table, std::string file, std::string path)
    : table_(&table), file_(std::move(file)), path_(std::move(path)) {}

std::string TomlSection::qualified(std::string_view key) const {
  if (key.empty()) return path_;  // the table itself
  return path_.empty() ? std::string(key) : path_ + "." + std::string(key);
}

void TomlSection::fail(const toml::node* node, std::string_view key, const std::string& what) const {
  if (node == nullptr) {
    throw InputError(fmt::format("{}: {}: {}", location(file_, table_->source()), qualified(key), what));
  }
  throw InputError(
      fmt::format("{}: {} = {}: {}", location(file_, node->source()), qualified(key), render(*node), what));
}

const toml::node* TomlSection::find(std::string_view key) {
  used_.emplace(key);
  return table_->get(key);
}

double TomlSection::number(std::string_view key, std::optional<double> fallback, const NumberRange& range) {
  const toml::node* node = find(key);
  if (node == nullptr) {
    if (fallback) return *fallback;
    fail(nullptr, key, "missing; expected " + range.describe());
  }
  if (!node->is_number()) fail(node, key, "expected " + range.describe());
  const double v = node->value<double>().value();
  if (!range.contains(v)) fail(node, key, "expected " + range.describe());
  return v;
}

std::int64_t TomlSection::integer(std::string_view key, std::optional<std::int64_t> fallback,
                                  std::int64_t min, std::int64_t max) {
  const std::string expected = fmt::format("expected an integer in [{}, {}]", min, max);
  const toml::node* node = find(key);
  if (node == nullptr) {
    if (fallback) return *fallback;
    fail(nullptr, key, "missing; " + expected);
  }
  if (!node->is_integer()) fail(node, key, expected);
  const std::int64_t v = node->value<std::int64_t>().value();
  if (v < min || v > max) fail(node, key, expected);
  return v;
}

std::vector<double> TomlSection::numbers(std::string_view key, const std::vector<double>* fallback, size_t count,
                                         const NumberRange& range) {
  const std::string expected = "expected an array of " + std::to_string(count) + " numbers, each " + range.describe();
  const toml::node* node = find(key);
  if (node == nullptr) {
    if (fallback) return *fallback;
    fail(nullptr, key, "missing; " + expected);
  }
  const toml::array* array = node->as_array();
  if (array == nullptr || array->size() != count) fail(node, key, expected);
  std::vector<double> v(count);
  for (size_t i = 0; i < count; ++i) {
    const toml::node& element = *array->get(i);
    if (!element.is_number()) fail(node, key, expected);
    v[i] = element.value<double>().value();
    if (!range.contains(v[i])) fail(node, key, expected);
  }
  return v;
}

std::vector<double> TomlSection::numberList(std::string_view key, size_t minCount, const NumberRange& range) {
  const toml::node* node = find(key);
  if (node == nullptr || node->as_array() == nullptr) fail(node, key, "expected an array of numbers");
  const size_t count = node->as_array()->size();
  if (count < minCount) fail(node, key, "expected an array of at least " + std::to_string(minCount) + " numbers");
  return numbers(key, nullptr, count, range);
}

size_t TomlSection::arraySize(std::string_view key) const {
  const toml::node* node = table_->get(key);
  return node != nullptr && node->is_array() ? node->as_array()->size() : 0;
}

glm::dvec3 TomlSection::vec3(std::string_view key, std::optional<glm::dvec3> fallback, const NumberRange& range) {
  const std::vector<double> f = fallback ? std::vector<double>{fallback->x, fallback->y, fallback->z} : std::vector<double>{};
  const std::vector<double> v = numbers(key, fallback ? &f : nullptr, 3, range);
  return {v[0], v[1], v[2]};
}

glm::dvec2 TomlSection::vec2(std::string_view key, std::optional<glm::dvec2> fallback, const NumberRange& range) {
  const std::vector<double> f = fallback ? std::vector<double>{fallback->x, fallback->y} : std::vector<double>{};
  const std::vector<double> v = numbers(key, fallback ? &f : nullptr, 2, range);
  return {v[0], v[1]};
}

bool TomlSection::boolean(std::string_view key, std::optional<bool> fallback) {
  const toml::node* node = find(key);
  if (node == nullptr) {
    if (fallback) return *fallback;
    fail(nullptr, key, "missing; expected true or false");
  }
  if (!node->is_boolean()) fail(node, key, "expected true or false");
  return node->value<bool>().value();
}

std::string TomlSection::oneOf(std::string_view key, std::optional<std::string> fallback,
                               const std::vector<std::string>& allowed) {
  const std::string expected = fmt::format("expected one of \"{}\"", fmt::join(allowed, "\", \""));
  const toml::node* node = find(key);
  if (node == nullptr) {
    if (fallback) return *fallback;
    fail(nullptr, key, "missing; " + expected);
  }
  if (!node->is_string()) fail(node, key, expected);
  std::string v = node->value<std::string>().value();
  for (const auto& a : allowed) {
    if (a == v) return v;
  }
  fail(node, key, expected);
}

std::optional<std::string> TomlSection::text(std::string_view key) {
  const toml::node* node = find(key);
  if (node == nullptr) return std::nullopt;
  if (!node->is_string() || node->value<std::string>()->empty()) fail(node, key, "expected a non-empty string");
  return node->value<std::string>().value();
}

std::optional<TomlSection> TomlSection::table(std::string_view key) {
  const toml::node* node = find(key);
  if (node == nullptr) return std::nullopt;
  if (!node->is_table()) fail(node, key, "expected a table ([" + qualified(key) + "])");
  return TomlSection(*node->as_table(), file_, qualified(key));
}

std::vector<TomlSection> TomlSection::tables(std::string_view key) {
  std::vector<TomlSection> result;
  const toml::node* node = find(key);
  if (node == nullptr) return result;
  const toml::array* array = node->as_array();
  if (array == nullptr || !array->is_array_of_tables()) {
    fail(node, key, "expected an array of tables ([[" + qualified(key) + "]])");
  }
  for (size_t i = 0; i < array->size(); ++i) {
    result.emplace_back(*array->get(i)->as_table(), file_, fmt::format("{}[{}]", qualified(key), i));
  }
  return result;
}

void TomlSection::finish() const {
  for (auto&& [key, node] : *table_) {
    if (used_.find(key.str()) == used_.end()) {
      std::vector<std::string> known(used_.begin(), used_.end());
      // The nearest known key, if it is a plausible typo.
      const std::string nearest = nearestName(key.str(), known);
      const std::string hint = nearest.empty() ? std::string() : fmt::format("did you mean '{}'? ", qualified(nearest));
      throw InputError(fmt::format("{}: unknown key '{}' ({}known here: {})", location(file_, key.source()), qualified(key.str()), hint,
                                   fmt::join(known, ", ")));
    }
  }
}

void TomlSection::failSection(const std::string& what) const {
  throw InputError(fmt::format("{}: [{}]: {}", location(file_, table_->source()), path_, what));
}

toml::table parseToml(const std::string& text, const std::string& file) {
  try {
    return toml::parse(text, file);
  } catch (const toml::parse_error& e) {
    throw InputError(fmt::format("{}: TOML syntax error: {}", location(file, e.source()), e.description()));
  }
}

toml::table parseTomlFile(const std::string& file) { return parseToml(readTextFile(file), file); }

toml::array tomlArray(const glm::dvec3& v) { return toml::array{v.x, v.y, v.z}; }
toml::array tomlArray(const glm::dvec2& v) { return toml::array{v.x, v.y}; }

}  // namespace forest::detail
