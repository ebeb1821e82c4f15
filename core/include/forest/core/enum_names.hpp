#pragma once
// One name table per enum: the names an option, a file or a report uses for its values, written
// once beside the enum, so that parsing, printing and the list of choices cannot disagree.
//
//   inline constexpr EnumNames<QueryMode, 2> kQueryModeNames{
//       "query mode", {{{QueryMode::Deterministic, "deterministic"}, {QueryMode::Async, "async"}}}};
//   kQueryModeNames.parse("async");        // QueryMode::Async
//   kQueryModeNames.name(QueryMode::Async) // "async"
//   kQueryModeNames.parse("x");            // throws InputError "query mode 'x': expected deterministic or async"
#include <fmt/format.h>

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "forest/core/error.hpp"

namespace forest {

template <class Enum, std::size_t N>
class EnumNames {
 public:
  struct Entry {
    Enum value;
    std::string_view name;
  };

  // `what` names the value in an error message ("shadow method"); the entries in the order
  // choices are listed (--help, errors, names()).
  constexpr EnumNames(std::string_view what, std::array<Entry, N> entries) : what_(what), entries_(entries) {}

  // The value named so; throws InputError naming every choice otherwise.
  Enum parse(std::string_view name) const {
    if (const std::optional<Enum> value = find(name)) return *value;
    throw InputError(fmt::format("{} '{}': expected {}", what_, name, choices()));
  }

  // The value named so, or nothing.
  constexpr std::optional<Enum> find(std::string_view name) const {
    for (const Entry& e : entries_)
      if (e.name == name) return e.value;
    return std::nullopt;
  }

  // The value's name ("?" for a value outside the table: a cast, never a parse).
  constexpr std::string_view name(Enum value) const {
    for (const Entry& e : entries_)
      if (e.value == value) return e.name;
    return "?";
  }

  // Every name, in the table's order (CLI::IsMember, help texts).
  std::vector<std::string> names() const {
    std::vector<std::string> out;
    for (const Entry& e : entries_) out.emplace_back(e.name);
    return out;
  }

  // Every value, in the table's order.
  std::array<Enum, N> values() const {
    std::array<Enum, N> out{};
    for (std::size_t i = 0; i < N; ++i) out[i] = entries_[i].value;
    return out;
  }

  // "a, b or c".
  std::string choices() const {
    std::string out;
    for (std::size_t i = 0; i < N; ++i) {
      if (i > 0) out += i + 1 == N ? " or " : ", ";
      out += entries_[i].name;
    }
    return out;
  }

 private:
  std::string_view what_;
  std::array<Entry, N> entries_;
};

}  // namespace forest
