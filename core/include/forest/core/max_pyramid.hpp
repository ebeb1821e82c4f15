#pragma once
// The largest value over any rectangle of a grid in constant time: a pyramid whose level k holds
// the maximum of each 2^k × 2^k block of the grid (a max mip chain, the CPU's form of a
// hierarchical depth buffer). A query answers with the maximum over the at most 2 × 2 blocks of
// the level where the rectangle spans at most two blocks each way — those blocks hold the
// rectangle, so the answer is at least its true maximum (the query is conservative) and at most
// the maximum over a 4^k-fold larger area.
#include <span>
#include <vector>

namespace forest {

class MaxPyramid {
 public:
  // The grid: `width` × `height` values, row by row. Keeps its storage between builds.
  void build(std::span<const float> values, int width, int height);
  // At least the largest value over columns [x0, x1] and rows [y0, y1] (inclusive; clamped to the
  // grid); −∞ for an empty range.
  float maxOver(int x0, int y0, int x1, int y1) const;
  int levels() const { return static_cast<int>(levels_.size()); }

 private:
  struct Level {
    int width = 0, height = 0;
    std::vector<float> values;
  };
  std::vector<Level> levels_;
};

}  // namespace forest
