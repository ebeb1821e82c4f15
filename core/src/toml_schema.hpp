#pragma once
// Reads one TOML table against a schema: every read names the key, its type and its range, and
// finish() rejects keys nobody read. Every error is one line:
//   file:line:column: section.key = value: expected <what>
#include <toml++/toml.h>

#include <glm/glm.hpp>

#include <cstdint>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

namespace forest::detail {

// An interval of allowed numbers; all values must be finite.
struct NumberRange {
  double min = -1e300;
  double max = 1e300;
  bool minOpen = false;  // min itself excluded
  bool maxOpen = false;

  bool contains(double v) const;
  std::string describe() const;
};
NumberRange anyFinite();
NumberRange positive();                      // (0, ∞)
NumberRange nonNegative();                   // [0, ∞)
NumberRange closed(double min, double max);  // [min, max]
NumberRange open(double min, double max);    // (min, max)

class TomlSection {
 public:
  TomlSection(const toml::table& table, std::string file, std::string path);

  // Each reader: `fallback` empty = required key.
  double number(std::string_view key, std::optional<double> fallback, const NumberRange& range);
  std::int64_t integer(std::string_view key, std::optional<std::int64_t> fallback, std::int64_t min,
                       std::int64_t max);
  glm::dvec3 vec3(std::string_view key, std::optional<glm::dvec3> fallback, const NumberRange& range);
  glm::dvec2 vec2(std::string_view key, std::optional<glm::dvec2> fallback, const NumberRange& range);
  bool boolean(std::string_view key, std::optional<bool> fallback);
  std::string oneOf(std::string_view key, std::optional<std::string> fallback,
                    const std::vector<std::string>& allowed);
  // A non-empty string; nullopt when absent.
  std::optional<std::string> text(std::string_view key);
  // Optional sub-table; nullopt when absent.
  std::optional<TomlSection> table(std::string_view key);
  // Array of tables ([[key]]); empty when absent.
  std::vector<TomlSection> tables(std::string_view key);

  // Whether the key is present; the key counts as known (finish() lists it among the valid keys).
  bool has(std::string_view key) const {
    used_.emplace(key);
    return table_->contains(key);
  }
  // An array of any length (at least `minCount`) of numbers in `range`; missing: an error.
  std::vector<double> numberList(std::string_view key, size_t minCount, const NumberRange& range);
  // Elements of the array at `key` (0 when absent or not an array): for keys of 2 or 3 numbers.
  size_t arraySize(std::string_view key) const;
  // Throws for the first key of this table that no reader asked for.
  void finish() const;

  // Throws an InputError located at the table about the whole section: "file:line:col: [path]: what".
  [[noreturn]] void failSection(const std::string& what) const;
  // Throws an InputError located at `node` (or at the table when null) about `key`.
  [[noreturn]] void fail(const toml::node* node, std::string_view key, const std::string& what) const;
  const std::string& file() const { return file_; }
  std::string qualified(std::string_view key) const;

 private:
  const toml::node* find(std::string_view key);
  std::vector<double> numbers(std::string_view key, const std::vector<double>* fallback, size_t count,
                              const NumberRange& range);

  const toml::table* table_;
  std::string file_;
  std::string path_;  // "camera", "props[2]", "" for the root
  mutable std::set<std::string, std::less<>> used_;  // keys asked for: the schema's known keys
};

// Parses TOML text; syntax errors become InputError "file:line:column: message".
toml::table parseToml(const std::string& text, const std::string& file);
// Parses a TOML file (missing/unreadable file → InputError naming it).
toml::table parseTomlFile(const std::string& file);

// Writers used to serialise documents back to TOML.
toml::array tomlArray(const glm::dvec3& v);
toml::array tomlArray(const glm::dvec2& v);

}  // namespace forest::detail
