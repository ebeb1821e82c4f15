#include "forest/core/suggest.hpp"

#include <algorithm>
#include <vector>

namespace forest {

std::size_t editDistance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

std::string nearestName(std::string_view given, std::span<const std::string> known) {
  std::string nearest;
  std::size_t best = std::string::npos;
  for (const std::string& k : known) {
    const std::size_t d = editDistance(given, k);
    if (d < best && 3 * d <= std::max<std::size_t>(3, k.size())) {
      best = d;
      nearest = k;
    }
  }
  return nearest;
}

}  // namespace forest
