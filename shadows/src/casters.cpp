#include "forest/shadows/casters.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

#include "forest/core/error.hpp"

namespace forest::shadows {
namespace {

using glm::dvec2;
using glm::dvec3;

constexpr int kMaxGridCellsPerSide = 256;

// Cells per side of the grid for `receivers` receivers: about one receiver per cell.
int gridSide(std::size_t receivers) {
  return std::clamp(static_cast<int>(std::ceil(std::sqrt(static_cast<double>(receivers)))), 1, kMaxGridCellsPerSide);
}

}  // namespace

std::pair<dvec3, dvec3> axesAcrossLight(const dvec3& l) {
  const dvec3 helper = std::abs(l.y) < 0.9 ? dvec3(0, 1, 0) : dvec3(1, 0, 0);
  const dvec3 u = glm::normalize(glm::cross(helper, l));
  return {u, glm::cross(l, u)};
}

bool sweptBoxMeetsBox(const Aabb& caster, const dvec3& l, const Aabb& receiver) {
  // Slab test of the ray t·l, t ≥ 0, against D = R ⊖ C.
  const dvec3 dMin = receiver.min - caster.max, dMax = receiver.max - caster.min;
  double tEnter = 0.0, tLeave = std::numeric_limits<double>::infinity();
  for (int axis = 0; axis < 3; ++axis) {
    if (l[axis] == 0.0) {
      if (dMin[axis] > 0.0 || dMax[axis] < 0.0) return false;  // the ray's line misses the slab
      continue;
    }
    double t0 = dMin[axis] / l[axis], t1 = dMax[axis] / l[axis];
    if (t0 > t1) std::swap(t0, t1);
    tEnter = std::max(tEnter, t0);
    tLeave = std::min(tLeave, t1);
    if (tEnter > tLeave) return false;
  }
  return true;
}

CasterSelector::CasterSelector(const dvec3& lightDirection, std::span<const Aabb> receivers) {
  rebuild(lightDirection, receivers);
}

void CasterSelector::reserve(std::size_t receivers) {
  receivers_.reserve(receivers);
  footprints_.reserve(receivers);
  deepest_.reserve(receivers);
  level_.reserve(receivers);
}

void CasterSelector::rebuild(const dvec3& lightDirection, std::span<const Aabb> receivers) {
  const double length = glm::length(lightDirection);
  if (!std::isfinite(length) || length == 0.0) throw InputError("light direction: expected a finite non-zero vector");
  receivers_.assign(receivers.begin(), receivers.end());
  light_ = lightDirection / length;
  std::tie(across_[0], across_[1]) = axesAcrossLight(light_);
  gridCells_ = glm::ivec2(0);
  for (Level& level : levels_) level.cells = glm::ivec2(0);
  if (receivers_.empty()) return;

  std::vector<Footprint>& footprints = footprints_;
  footprints.clear();
  deepest_.clear();
  dvec2 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  for (const Aabb& r : receivers_) {
    const Footprint f = footprint(r);
    footprints.push_back(f);
    deepest_.push_back(glm::dot(light_, r.centre()) + 0.5 * glm::dot(glm::abs(light_), r.extent()));
    lo = glm::min(lo, f.min);
    hi = glm::max(hi, f.max);
  }
  const int side = gridSide(receivers_.size());
  gridCells_ = glm::ivec2(side);
  gridMin_ = lo;
  cellSize_ = glm::max((hi - lo) / static_cast<double>(side), dvec2(1e-300));
  // A hierarchical grid: level k's cells are kLevelRatio^k times level 0's; each receiver goes to
  // the first level where its footprint spans at most kLargeFootprintCells cells an axis (a few
  // large ones — terrain tiles at a landscape's distance, stretched along a low sun — to coarse
  // levels, where they do not crowd the fine cells), and into every cell of it that it overlaps.
  level_.assign(footprints.size(), 0);
  int levels = 1;
  for (std::uint32_t i = 0; i < footprints.size(); ++i) {
    const dvec2 extent = footprints[i].max - footprints[i].min;
    double reach = kLargeFootprintCells;
    int k = 0;
    while (k + 1 < kLevels && (extent.x > reach * cellSize_.x || extent.y > reach * cellSize_.y)) ++k, reach *= kLevelRatio;
    level_[i] = static_cast<std::uint8_t>(k);
    levels = std::max(levels, k + 1);
  }
  for (int k = 0; k < kLevels; ++k) {
    Level& level = levels_[static_cast<size_t>(k)];
    if (k >= levels) {
      level.cells = glm::ivec2(0);
      continue;
    }
    const int ratio = static_cast<int>(std::pow(kLevelRatio, k));
    level.cells = glm::ivec2((side + ratio - 1) / ratio);
    level.cellSize = cellSize_ * static_cast<double>(ratio);
    fileLevel(level, static_cast<std::uint8_t>(k));
  }
}

glm::ivec2 CasterSelector::cellOf(const Level& level, const dvec2& p) const {
  const dvec2 cell = glm::floor((p - gridMin_) / level.cellSize);
  return glm::clamp(glm::ivec2(glm::clamp(cell, dvec2(-1.0), dvec2(level.cells))), glm::ivec2(0), level.cells - 1);
}

void CasterSelector::fileLevel(Level& level, std::uint8_t k) {
  // A counting sort of the level's receivers into every cell they overlap: count, prefix sums, fill.
  const size_t cells = static_cast<size_t>(level.cells.x) * level.cells.y;
  level.start.assign(cells + 1, 0);
  const auto forEachCell = [&](std::uint32_t i, auto&& visit) {
    const glm::ivec2 a = cellOf(level, footprints_[i].min), b = cellOf(level, footprints_[i].max);
    for (int y = a.y; y <= b.y; ++y)
      for (int x = a.x; x <= b.x; ++x) visit(static_cast<size_t>(y) * level.cells.x + x);
  };
  for (std::uint32_t i = 0; i < footprints_.size(); ++i)
    if (level_[i] == k) forEachCell(i, [&](size_t c) { ++level.start[c + 1]; });
  for (size_t c = 0; c < cells; ++c) level.start[c + 1] += level.start[c];
  level.items.resize(level.start[cells]);
  for (std::uint32_t i = 0; i < footprints_.size(); ++i)
    if (level_[i] == k) forEachCell(i, [&](size_t c) { level.items[level.start[c]++] = i; });
  // Each start was moved to its cell's end, which is the next cell's start: shift back by one.
  for (size_t c = cells; c > 0; --c) level.start[c] = level.start[c - 1];
  level.start[0] = 0;
  // Deepest first within each cell (ties by index: the same order every run).
  for (size_t c = 0; c < cells; ++c)
    std::sort(level.items.begin() + level.start[c], level.items.begin() + level.start[c + 1], [&](std::uint32_t a, std::uint32_t b) {
      return deepest_[a] != deepest_[b] ? deepest_[a] > deepest_[b] : a < b;
    });
}

CasterSelector::Footprint CasterSelector::footprint(const Aabb& box) const {
  // Projection of the box onto the plane across the light: centre ± the projected half extent.
  const dvec3 centre = box.centre(), half = 0.5 * box.extent();
  Footprint f;
  for (int i = 0; i < 2; ++i) {
    const double c = glm::dot(across_[i], centre);
    const double r = glm::dot(glm::abs(across_[i]), half);
    f.min[i] = c - r;
    f.max[i] = c + r;
  }
  return f;
}

bool CasterSelector::needed(const Aabb& caster) const {
  if (receivers_.empty()) return false;
  const Footprint f = footprint(caster);
  // Footprints entirely outside the grid meet no receiver.
  const dvec2 gridMax = gridMin_ + cellSize_ * dvec2(gridCells_);
  if (f.max.x < gridMin_.x || f.max.y < gridMin_.y || f.min.x > gridMax.x || f.min.y > gridMax.y) return false;
  // The sweep's points lie at least as deep along the light as the caster's nearest point.
  // (Less a rounding margin: a receiver that touches the sweep's first plane stays to the exact test.)
  double shallowest = glm::dot(light_, caster.centre()) - 0.5 * glm::dot(glm::abs(light_), caster.extent());
  shallowest -= 1e-9 * (1.0 + std::abs(shallowest));
  // A receiver that may meet the sweep is filed in every cell of its level that its footprint
  // overlaps, so in one of the caster's there.
  for (const Level& level : levels_) {
    if (level.cells.x == 0) continue;
    const glm::ivec2 a = cellOf(level, f.min), b = cellOf(level, f.max);
    for (int y = a.y; y <= b.y; ++y)
      for (int x = a.x; x <= b.x; ++x) {
        const size_t c = static_cast<size_t>(y) * level.cells.x + x;
        for (std::uint32_t k = level.start[c]; k < level.start[c + 1]; ++k) {
          const std::uint32_t item = level.items[k];
          if (deepest_[item] < shallowest) break;  // this one and the rest of the cell end before the caster
          const Footprint& r = footprints_[item];
          if (r.max.x < f.min.x || r.max.y < f.min.y || r.min.x > f.max.x || r.min.y > f.max.y) continue;
          if (sweptBoxMeetsBox(caster, light_, receivers_[item])) return true;
        }
      }
  }
  return false;
}

std::vector<std::uint32_t> CasterSelector::select(std::span<const Aabb> casters) const {
  std::vector<std::uint32_t> selected;
  select(casters, selected);
  return selected;
}

void CasterSelector::select(std::span<const Aabb> casters, std::vector<std::uint32_t>& selected) const {
  selected.clear();
  for (std::uint32_t i = 0; i < casters.size(); ++i)
    if (needed(casters[i])) selected.push_back(i);
}

bool mayIntersect(const ConvexBody& body, const Aabb& box) {
  if (body.empty()) return false;
  const Aabb bodyBox = body.bounds();
  for (int axis = 0; axis < 3; ++axis)
    if (bodyBox.max[axis] < box.min[axis] || bodyBox.min[axis] > box.max[axis]) return false;
  const double tolerance = body.tolerance();
  for (const Polygon& face : body.polygons()) {
    const dvec3 normal = polygonNormal(face);
    if (normal == dvec3(0.0)) continue;
    // The box corner farthest against the normal: if even it is outside, the box is.
    const dvec3 nearest(normal.x > 0 ? box.min.x : box.max.x, normal.y > 0 ? box.min.y : box.max.y,
                        normal.z > 0 ? box.min.z : box.max.z);
    if (glm::dot(normal, nearest - face[0]) > tolerance) return false;
  }
  return true;
}

}  // namespace forest::shadows
