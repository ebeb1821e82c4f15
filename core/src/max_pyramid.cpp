#include "forest/core/max_pyramid.hpp"

#include <algorithm>
#include <limits>

#include "forest/core/error.hpp"

namespace forest {

void MaxPyramid::build(std::span<const float> values, int width, int height) {
  if (width < 0 || height < 0 || values.size() != static_cast<size_t>(width) * static_cast<size_t>(height))
    throw Error("MaxPyramid::build: the values are not width × height");
  levels_.resize(1);
  levels_[0] = {width, height, std::vector<float>(values.begin(), values.end())};
  // Level k + 1 from level k: each value the largest of its 2 × 2 block (one or two at an odd edge).
  while (levels_.back().width > 1 || levels_.back().height > 1) {
    const Level& fine = levels_.back();
    Level coarse{(fine.width + 1) / 2, (fine.height + 1) / 2, {}};
    coarse.values.resize(static_cast<size_t>(coarse.width) * static_cast<size_t>(coarse.height));
    for (int y = 0; y < coarse.height; ++y)
      for (int x = 0; x < coarse.width; ++x) {
        const int fx = 2 * x, fy = 2 * y, gx = std::min(fx + 1, fine.width - 1), gy = std::min(fy + 1, fine.height - 1);
        const auto at = [&](int cx, int cy) { return fine.values[static_cast<size_t>(cy) * static_cast<size_t>(fine.width) + cx]; };
        coarse.values[static_cast<size_t>(y) * static_cast<size_t>(coarse.width) + x] =
            std::max({at(fx, fy), at(gx, fy), at(fx, gy), at(gx, gy)});
      }
    levels_.push_back(std::move(coarse));
  }
}

float MaxPyramid::maxOver(int x0, int y0, int x1, int y1) const {
  if (levels_.empty()) return -std::numeric_limits<float>::infinity();
  const Level& grid = levels_[0];
  x0 = std::max(x0, 0);
  y0 = std::max(y0, 0);
  x1 = std::min(x1, grid.width - 1);
  y1 = std::min(y1, grid.height - 1);
  if (x0 > x1 || y0 > y1) return -std::numeric_limits<float>::infinity();
  // The finest level where the range spans at most two blocks each way.
  size_t k = 0;
  while ((x1 >> k) - (x0 >> k) > 1 || (y1 >> k) - (y0 >> k) > 1) ++k;
  const Level& level = levels_[k];
  float largest = -std::numeric_limits<float>::infinity();
  for (int y = y0 >> k; y <= y1 >> k; ++y)
    for (int x = x0 >> k; x <= x1 >> k; ++x)
      largest = std::max(largest, level.values[static_cast<size_t>(y) * static_cast<size_t>(level.width) + x]);
  return largest;
}

}  // namespace forest
