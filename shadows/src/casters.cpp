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
  cellItems_.reserve(receivers);
  largeItems_.reserve(receivers);
  const size_t side = static_cast<size_t>(gridSide(receivers));
  cellStart_.reserve(side * side + 1);
}

void CasterSelector::rebuild(const dvec3& lightDirection, std::span<const Aabb> receivers) {
  const double length = glm::length(lightDirection);
  if (!std::isfinite(length) || length == 0.0) throw InputError("light direction: expected a finite non-zero vector");
  receivers_.assign(receivers.begin(), receivers.end());
  light_ = lightDirection / length;
  std::tie(across_[0], across_[1]) = axesAcrossLight(light_);
  gridCells_ = glm::ivec2(0);
  cellStart_.clear();
  cellItems_.clear();
  if (receivers_.empty()) return;

  std::vector<Footprint>& footprints = footprints_;
  footprints.clear();
  dvec2 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  for (const Aabb& r : receivers_) {
    const Footprint f = footprint(r);
    footprints.push_back(f);
    lo = glm::min(lo, f.min);
    hi = glm::max(hi, f.max);
  }
  const int side = gridSide(receivers_.size());
  gridCells_ = glm::ivec2(side);
  gridMin_ = lo;
  cellSize_ = glm::max((hi - lo) / static_cast<double>(side), dvec2(1e-300));
  // A few large receivers (terrain tiles at a landscape's distance, stretched along a low sun)
  // would widen every search by their footprint: they are kept apart, in a list each caster
  // scans, and the grid's search reach is the largest footprint of the rest.
  largeItems_.clear();
  largestFootprint_ = dvec2(0.0);
  const dvec2 largeAbove = kLargeFootprintCells * cellSize_;
  const auto isLarge = [&](std::uint32_t i) {
    const dvec2 extent = footprints[i].max - footprints[i].min;
    return extent.x > largeAbove.x || extent.y > largeAbove.y;
  };
  for (std::uint32_t i = 0; i < footprints.size(); ++i) {
    if (isLarge(i)) largeItems_.push_back(i);
    else largestFootprint_ = glm::max(largestFootprint_, footprints[i].max - footprints[i].min);
  }
  // Counting sort by the low corner's cell: count, prefix sums, fill (each cell keeps increasing
  // order).
  const size_t cells = static_cast<size_t>(side) * side;
  cellStart_.assign(cells + 1, 0);
  auto cellIndex = [&](std::uint32_t i) {
    const glm::ivec2 a = cellOf(footprints[i].min);
    return static_cast<size_t>(a.y) * side + a.x;
  };
  for (std::uint32_t i = 0; i < footprints.size(); ++i)
    if (!isLarge(i)) ++cellStart_[cellIndex(i) + 1];
  for (size_t c = 0; c < cells; ++c) cellStart_[c + 1] += cellStart_[c];
  cellItems_.resize(footprints.size() - largeItems_.size());
  for (std::uint32_t i = 0; i < footprints.size(); ++i)
    if (!isLarge(i)) cellItems_[cellStart_[cellIndex(i)]++] = i;
  // Each start was moved to its cell's end, which is the next cell's start: shift back by one.
  for (size_t c = cells; c > 0; --c) cellStart_[c] = cellStart_[c - 1];
  cellStart_[0] = 0;
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

glm::ivec2 CasterSelector::cellOf(const dvec2& p) const {
  const dvec2 cell = glm::floor((p - gridMin_) / cellSize_);
  return glm::clamp(glm::ivec2(glm::clamp(cell, dvec2(-1.0), dvec2(gridCells_))), glm::ivec2(0), gridCells_ - 1);
}

bool CasterSelector::needed(const Aabb& caster) const {
  if (receivers_.empty()) return false;
  const Footprint f = footprint(caster);
  // Footprints entirely outside the grid meet no receiver.
  const dvec2 gridMax = gridMin_ + cellSize_ * dvec2(gridCells_);
  if (f.max.x < gridMin_.x || f.max.y < gridMin_.y || f.min.x > gridMax.x || f.min.y > gridMax.y) return false;
  // A receiver filed in cell (x, y) has its low corner there; it can reach this footprint only if
  // that corner is within the largest footprint below the footprint's low corner.
  for (std::uint32_t k : largeItems_) {
    const Footprint& r = footprints_[k];  // apart in the plane across the light: the sweep cannot meet it
    if (r.max.x < f.min.x || r.max.y < f.min.y || r.min.x > f.max.x || r.min.y > f.max.y) continue;
    if (sweptBoxMeetsBox(caster, light_, receivers_[k])) return true;
  }
  const glm::ivec2 a = cellOf(f.min - largestFootprint_), b = cellOf(f.max);
  for (int y = a.y; y <= b.y; ++y)
    for (int x = a.x; x <= b.x; ++x) {
      const size_t c = static_cast<size_t>(y) * gridCells_.x + x;
      for (std::uint32_t k = cellStart_[c]; k < cellStart_[c + 1]; ++k)
        if (sweptBoxMeetsBox(caster, light_, receivers_[cellItems_[k]])) return true;
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
