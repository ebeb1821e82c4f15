#pragma once
// "Did you mean" hints for misspelled names (scene keys, command-line flags).
#include <span>
#include <string>
#include <string_view>

namespace forest {

// Levenshtein distance (insertions, deletions, substitutions).
std::size_t editDistance(std::string_view a, std::string_view b);

// The known name nearest to `given` when it is a plausible typo of it (at most a third of its
// letters differ, at least one allowed); empty when none is.
std::string nearestName(std::string_view given, std::span<const std::string> known);

}  // namespace forest
