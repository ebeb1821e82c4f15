#include "forest/shadows/receiver_mask.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <span>

#include "forest/core/avx2_clone.hpp"
#include "forest/core/error.hpp"
#include "forest/core/polygon2d.hpp"

namespace forest::shadows {

using glm::dvec2;
using glm::dvec3;
using glm::dvec4;

namespace {
// The GPU places a pixel's point from float32 depth and rays; this much map depth covers that.
constexpr double kDepthTolerance = 1e-5;
}  // namespace

void ReceiverMask::reset(const ShadowSetup& setup, int mapSize, int cells) {
  if (cells < 1 || mapSize < 1) throw Error("ReceiverMask: cells and map size must be positive");
  worldToShadowClip_ = setup.worldToShadowClip;
  linearDepth_ = setup.linearDepth;
  worldToLightDepth_ = setup.worldToLightDepth;
  mapSize_ = mapSize;
  side_ = cells;
  receivers_ = 0;
  everywhere_ = false;
  cells_.assign(static_cast<size_t>(cells) * cells, Cell{0, 0});
}

double ReceiverMask::depthOf(const dvec3& world, const dvec4& clip) const {
  return linearDepth_ ? glm::dot(worldToLightDepth_, dvec4(world, 1.0)) : clip.z / clip.w;
}

namespace {

// [−1, 1] → [0, subCells), clamped first, then truncated: the same as floor then clamp, without a
// call to floor (no SSE4.1 rounding instruction in the baseline x86-64 build). NaN gives 0, not a
// conversion without a value (std::max(0, NaN) is 0), so that placeRow need not branch around it.
// Inlined: a frame calls it twice per sun-facing pixel.
[[gnu::always_inline]] inline int subCellAt(double ndc, int subCells) {
  return static_cast<int>(std::max(0.0, std::min((ndc + 1.0) * 0.5 * subCells, subCells - 1.0)));
}

// Map depth in 16 bits: [−1, 1] (clip z / w, or tsm's linear light depth) onto 0 … 65535, clamped
// (a receiver beyond the ends counts at them: farther for one past −1, as far as can be for one past
// 1). Rounded up for receivers (a code no nearer the light than the point, and without a branch:
// a frame adds one per pixel), down for casters, so the test errs toward keeping a caster: by at
// most 3·10⁻⁵ of the depth range, as kDepthTolerance (1·10⁻⁵) already does.
constexpr double kCodesPerUnit = 0.5 * 65535.0;
[[gnu::always_inline]] inline std::uint16_t depthCodeAtOrBeyond(double depth) {
  return static_cast<std::uint16_t>(std::min(65535.0, (std::clamp(depth, -1.0, 1.0) + 1.0) * kCodesPerUnit + 1.0));
}
std::uint16_t depthCodeAtOrBefore(double depth) {
  return static_cast<std::uint16_t>((std::clamp(depth, -1.0, 1.0) + 1.0) * kCodesPerUnit);
}

}  // namespace

int ReceiverMask::subCellOf(double ndc) const { return subCellAt(ndc, side_ * kSubCells); }

// Places receiver points. The mask's fields are copied into it, so that the per-pixel loop keeps
// them in registers (a write to a cell could alias them otherwise); done() hands the counts back.
struct ReceiverMask::Writer {
  explicit Writer(ReceiverMask& target) : mask(target), cells(target.cells_.data()), side(target.side_) {}
  void done() {
    mask.receivers_ += receivers;
    mask.everywhere_ = mask.everywhere_ || everywhere;
  }
  // A receiver at clip position h (invW: 1 / h.w) with map depth `depth`.
  void add(const dvec4& h, double invW, double depth) {
    const double x = h.x * invW, y = h.y * invW;
    if (!(h.w > 0.0) || !std::isfinite(x) || !std::isfinite(y) || !std::isfinite(depth)) {
      everywhere = true;  // a receiver the map cannot place: every caster may shadow it
      return;
    }
    place(static_cast<unsigned>(subCellAt(x, side * kSubCells)), static_cast<unsigned>(subCellAt(y, side * kSubCells)),
          depthCodeAtOrBeyond(depth));
  }
  // A receiver in sub-cell (sx, sy) with depth code `code`.
  [[gnu::always_inline]] void place(unsigned sx, unsigned sy, std::uint16_t code) {
    ++receivers;
    Cell& cell = cells[static_cast<size_t>(sy / kSubCells) * static_cast<size_t>(side) + sx / kSubCells];
    cell.occupied = static_cast<std::uint16_t>(cell.occupied | 1u << (kSubCells * (sy % kSubCells) + sx % kSubCells));
    cell.farthest = std::max(cell.farthest, code);
  }

  ReceiverMask& mask;
  Cell* cells;
  int side;
  int receivers = 0;
  bool everywhere = false;
};

void ReceiverMask::add(const dvec3& world) {
  const dvec4 h = worldToShadowClip_ * dvec4(world, 1.0);
  Writer writer(*this);
  writer.add(h, 1.0 / h.w, depthOf(world, h));
  writer.done();
}

namespace {

// Where placeRow puts a pixel: its sub-cell (sy << 16 | sx), or one of these.
constexpr std::uint32_t kNoReceiver = ~std::uint32_t{0}, kUnplaceable = kNoReceiver - 1u;

// A map coordinate along one row of pixels as a function of a pixel's eye depth z and column x:
// atEye + z · (atRow + x · perColumn).
struct RowAffine {
  double atEye, atRow, perColumn;
  double at(double z, double x) const { return atEye + z * (atRow + x * perColumn); }
};

// Places one row's pixels, as Writer::add places a point, without branches so that the compiler
// vectorises it (the scatter into cells follows in addEyeRow). clipX, clipY, clipZ, clipW: the map's
// clip coordinates; lightDepth: tsm's linear light depth (kLinearDepth), else clip z / w.
template <bool kLinearDepth>
[[gnu::always_inline]] inline void placeRow(const float* __restrict depths, const float* __restrict columns, std::size_t count,
                                            RowAffine clipX, RowAffine clipY, RowAffine clipZ, RowAffine clipW, RowAffine lightDepth,
                                            double zMin, double zMax, int subCells, std::uint32_t* __restrict placed,
                                            std::uint16_t* __restrict codes) {
  const double largest = std::numeric_limits<double>::max();
  for (std::size_t i = 0; i < count; ++i) {
    const double z = depths[i], x = columns[i];
    const double w = clipW.at(z, x);
    const double invW = 1.0 / w;  // one division per point: clip z / w is h.z · invW
    const double nx = clipX.at(z, x) * invW, ny = clipY.at(z, x) * invW;
    const double depth = kLinearDepth ? lightDepth.at(z, x) : clipZ.at(z, x) * invW;
    const bool receiver = (z >= zMin) & (z <= zMax);
    // A receiver the map cannot place (behind the light's projection, or not finite: NaN fails
    // every comparison): every caster may shadow it.
    const bool placeable = (w > 0.0) & (std::abs(nx) <= largest) & (std::abs(ny) <= largest) & (std::abs(depth) <= largest);
    const unsigned sx = static_cast<unsigned>(subCellAt(nx, subCells)), sy = static_cast<unsigned>(subCellAt(ny, subCells));
    placed[i] = receiver ? (placeable ? sy << 16 | sx : kUnplaceable) : kNoReceiver;
    codes[i] = depthCodeAtOrBeyond(depth);  // NaN: 65535, unused
  }
}
// One function per depth kind, each with its AVX2 copy: the choice of depth is a template
// argument (a run-time choice inside the loop keeps it from vectorising), and target_clones takes
// plain functions.
FOREST_AVX2_CLONE void placeRowLinearDepth(const float* depths, const float* columns, std::size_t count, RowAffine clipX,
                                           RowAffine clipY, RowAffine clipZ, RowAffine clipW, RowAffine lightDepth, double zMin,
                                           double zMax, int subCells, std::uint32_t* placed, std::uint16_t* codes) {
  placeRow<true>(depths, columns, count, clipX, clipY, clipZ, clipW, lightDepth, zMin, zMax, subCells, placed, codes);
}
FOREST_AVX2_CLONE void placeRowClipDepth(const float* depths, const float* columns, std::size_t count, RowAffine clipX,
                                         RowAffine clipY, RowAffine clipZ, RowAffine clipW, RowAffine lightDepth, double zMin,
                                         double zMax, int subCells, std::uint32_t* placed, std::uint16_t* codes) {
  placeRow<false>(depths, columns, count, clipX, clipY, clipZ, clipW, lightDepth, zMin, zMax, subCells, placed, codes);
}

}  // namespace

void ReceiverMask::addEyeRow(const EyeRays& rays, float row, std::span<const float> columns, std::span<const float> depths,
                             double zMin, double zMax) {
  // M (eye + z (f + y u + x r)) = M eye + z (M (f + y u) + x M r): the map's clip position, and
  // likewise tsm's linear light depth, is affine in z·(1, x) along a row.
  const dvec3 rowRay = rays.forward + static_cast<double>(row) * rays.up;
  const dvec4 origin = worldToShadowClip_ * dvec4(rays.eye, 1.0);
  const dvec4 base = worldToShadowClip_ * dvec4(rowRay, 0.0);
  const dvec4 right = worldToShadowClip_ * dvec4(rays.right, 0.0);
  const RowAffine lightDepth{glm::dot(worldToLightDepth_, dvec4(rays.eye, 1.0)), glm::dot(worldToLightDepth_, dvec4(rowRay, 0.0)),
                             glm::dot(worldToLightDepth_, dvec4(rays.right, 0.0))};
  const size_t count = std::min(columns.size(), depths.size());
  static_assert(kSubCells * 1024 <= 65536, "placeRow packs a sub-cell's x and y into 16 bits each");
  if (side_ > 1024) throw Error("ReceiverMask::addEyeRow: more than 1024 cells a side");
  rowPlaced_.resize(count);
  rowCodes_.resize(count);
  (linearDepth_ ? placeRowLinearDepth : placeRowClipDepth)(depths.data(), columns.data(), count, {origin.x, base.x, right.x},
                                                          {origin.y, base.y, right.y}, {origin.z, base.z, right.z},
                                                          {origin.w, base.w, right.w}, lightDepth, zMin, zMax, side_ * kSubCells,
                                                          rowPlaced_.data(), rowCodes_.data());
  Writer writer(*this);
  for (size_t i = 0; i < count; ++i) {
    const std::uint32_t placed = rowPlaced_[i];
    if (placed == kNoReceiver) continue;
    if (placed == kUnplaceable) {
      writer.everywhere = true;
      continue;
    }
    writer.place(placed & 0xffffu, placed >> 16, rowCodes_[i]);
  }
  writer.done();
}

void ReceiverMask::merge(const ReceiverMask& other, int part, int parts) {
  if (other.side_ != side_ || other.mapSize_ != mapSize_ || other.worldToShadowClip_ != worldToShadowClip_)
    throw Error("ReceiverMask::merge: the masks are of different maps or cells");
  if (parts < 1 || part < 0 || part >= parts) throw Error("ReceiverMask::merge: expected a part in [0, parts)");
  if (part == 0) {
    receivers_ += other.receivers_;
    everywhere_ = everywhere_ || other.everywhere_;
  }
  const size_t from = cells_.size() * static_cast<size_t>(part) / static_cast<size_t>(parts);
  const size_t to = cells_.size() * static_cast<size_t>(part + 1) / static_cast<size_t>(parts);
  for (size_t i = from; i < to; ++i) {
    cells_[i].farthest = std::max(cells_[i].farthest, other.cells_[i].farthest);
    cells_[i].occupied = static_cast<std::uint16_t>(cells_[i].occupied | other.cells_[i].occupied);
  }
}

std::optional<double> ReceiverMask::farthestReading(int x, int y, double reachTexels) const {
  if (side_ == 0) return std::nullopt;
  // Sub-cell s reads texel x when x + 0.5 lies in [s · perSubCell − reach, (s + 1) · perSubCell + reach].
  const double perSubCell = static_cast<double>(mapSize_) / (side_ * kSubCells);
  const int last = side_ * kSubCells - 1;
  auto range = [&](int t) {
    const double centre = t + 0.5;
    return std::pair<int, int>(std::max(0, static_cast<int>(std::ceil((centre - reachTexels) / perSubCell - 1.0))),
                               std::min(last, static_cast<int>(std::floor((centre + reachTexels) / perSubCell))));
  };
  const auto [sx0, sx1] = range(x);
  const auto [sy0, sy1] = range(y);
  int farthest = -1;
  for (int sy = sy0; sy <= sy1; ++sy)
    for (int sx = sx0; sx <= sx1; ++sx) {
      const Cell& cell = cells_[static_cast<size_t>(sy / kSubCells) * side_ + sx / kSubCells];
      if ((cell.occupied >> (kSubCells * (sy % kSubCells) + sx % kSubCells) & 1u) != 0) farthest = std::max<int>(farthest, cell.farthest);
    }
  if (farthest < 0) return std::nullopt;
  return farthest / kCodesPerUnit - 1.0;  // a code at or beyond its receivers' depths (depthCodeAtOrBeyond)
}

namespace {
// A cell's occupied bits folded onto one row (which sub-cell columns i occur) or one column (which rows j).
unsigned subColumns(unsigned bits) {
  unsigned columns = 0;
  for (int j = 0; j < 4; ++j) columns |= bits >> (4 * j) & 0xFu;
  return columns;
}
unsigned subRows(unsigned bits) {
  unsigned rows = 0;
  for (int j = 0; j < 4; ++j) rows |= (bits >> (4 * j) & 0xFu) != 0 ? 1u << j : 0u;
  return rows;
}
}  // namespace

TexelRect ReceiverMask::texelsRead(double reachTexels) const {
  static_assert(kSubCells == 4, "subColumns and subRows read 4 × 4 bits");
  if (everywhere_) return TexelRect{0, 0, mapSize_, mapSize_};
  // The occupied sub-cells' bounds, from the cells' bits ORed per column of cells and kept for the
  // first and last occupied rows (a frame's fill leaves them to this: tracking them per point cost
  // its loop ~10%; the inner loop has no branch and vectorises).
  std::vector<std::uint16_t> columnBits(static_cast<size_t>(side_), 0);
  int cy0 = side_, cy1 = -1;
  std::uint16_t firstRowBits = 0, lastRowBits = 0;
  for (int cy = 0; cy < side_; ++cy) {
    const Cell* row = cells_.data() + static_cast<size_t>(cy) * side_;
    std::uint16_t any = 0;
    for (int cx = 0; cx < side_; ++cx) {
      columnBits[static_cast<size_t>(cx)] = static_cast<std::uint16_t>(columnBits[static_cast<size_t>(cx)] | row[cx].occupied);
      any = static_cast<std::uint16_t>(any | row[cx].occupied);
    }
    if (any == 0) continue;
    if (cy1 < 0) {
      cy0 = cy;
      firstRowBits = any;
    }
    cy1 = cy;
    lastRowBits = any;
  }
  if (cy1 < 0) return TexelRect{};  // no receivers
  const auto occupied = [](std::uint16_t b) { return b != 0; };
  const int cx0 = static_cast<int>(std::find_if(columnBits.begin(), columnBits.end(), occupied) - columnBits.begin());
  const int cx1 = static_cast<int>(columnBits.rend() - std::find_if(columnBits.rbegin(), columnBits.rend(), occupied)) - 1;
  const glm::ivec2 lower(cx0 * kSubCells + std::countr_zero(subColumns(columnBits[static_cast<size_t>(cx0)])),
                         cy0 * kSubCells + std::countr_zero(subRows(firstRowBits)));
  const glm::ivec2 upper(cx1 * kSubCells + 31 - std::countl_zero(subColumns(columnBits[static_cast<size_t>(cx1)])),
                         cy1 * kSubCells + 31 - std::countl_zero(subRows(lastRowBits)));
  // Sub-cell s spans texels [s, s + 1) · mapSize / subCells; a lookup in it reads up to the reach beyond.
  const double texelsPerSubCell = static_cast<double>(mapSize_) / (side_ * kSubCells);
  auto first = [&](int s) { return std::max(0, static_cast<int>(std::floor(s * texelsPerSubCell - reachTexels))); };
  auto end = [&](int s) { return std::min(mapSize_, static_cast<int>(std::ceil((s + 1) * texelsPerSubCell + reachTexels))); };
  return TexelRect{first(lower.x), first(lower.y), end(upper.x), end(upper.y)};
}

bool ReceiverMask::mayShadow(const Aabb& caster, double reachTexels) const {
  std::array<dvec3, 8> corners;
  for (int c = 0; c < 8; ++c) corners[static_cast<size_t>(c)] = caster.corner(c);
  return mayShadow(std::span<const dvec3>(corners), reachTexels);
}

bool ReceiverMask::mayShadow(std::span<const dvec3> caster, double reachTexels) const {
  if (everywhere_) return true;
  if (side_ == 0) return false;
  if (caster.size() > kMaxCorners) throw Error("ReceiverMask::mayShadow: more than 16 corners");
  // The body's footprint in the map (x, y) and its nearest depth: over a convex body, a projective
  // map's x/w, y/w and depth are extreme at corners when w > 0 at all of them (w is affine).
  double x0 = std::numeric_limits<double>::infinity(), x1 = -x0, y0 = x0, y1 = -x0, nearest = x0;
  std::array<dvec2, kMaxCorners> corners;
  for (size_t c = 0; c < caster.size(); ++c) {
    const dvec3& p = caster[c];
    const dvec4 h = worldToShadowClip_ * dvec4(p, 1.0);
    if (!(h.w > 0.0)) return true;
    const double x = h.x / h.w, y = h.y / h.w, z = depthOf(p, h);
    corners[c] = dvec2(x, y);
    x0 = std::min(x0, x);
    x1 = std::max(x1, x);
    y0 = std::min(y0, y);
    y1 = std::max(y1, y);
    nearest = std::min(nearest, z);
  }
  // The body's outline: the hull of its corners (a projective map with w > 0 keeps it convex),
  // found when a sub-cell first needs it (most boxes end at a cell's depth or bits).
  std::array<dvec2, 2 * kMaxCorners> hull;
  size_t hullSize = 0;
  bool hullFound = false;
  // Grown by the reach, in map units (2 / mapSize per texel).
  const double grow = reachTexels * 2.0 / mapSize_;
  const int subCells = side_ * kSubCells;
  const double subCellSize = 2.0 / subCells;
  // Whether sub-cell (sx, sy), grown by the reach, meets the outline: separated by no edge of it
  // (its x and y range meet the outline's: the loops below stay inside them).
  auto meetsOutline = [&](int sx, int sy) {
    if (!hullFound) {
      hullSize = convexHullInPlace(std::span<dvec2>(corners.data(), caster.size()), hull);
      hullFound = true;
    }
    if (hullSize < 3) return true;  // a flat outline: its bounding rectangle decides
    const dvec2 centre((sx + 0.5) * subCellSize - 1.0, (sy + 0.5) * subCellSize - 1.0);
    const double half = 0.5 * subCellSize + grow;
    for (size_t e = 0; e < hullSize; ++e) {
      const dvec2 a = hull[e], b = hull[(e + 1) % hullSize];
      const dvec2 outward(b.y - a.y, a.x - b.x);  // the hull runs counter-clockwise
      if (glm::dot(outward, centre - a) > (std::abs(outward.x) + std::abs(outward.y)) * half) return false;
    }
    return true;
  };
  const std::uint16_t nearestCode = depthCodeAtOrBefore(nearest - kDepthTolerance);
  const int sx0 = subCellOf(x0 - grow), sx1 = subCellOf(x1 + grow), sy0 = subCellOf(y0 - grow), sy1 = subCellOf(y1 + grow);
  for (int cy = sy0 / kSubCells; cy <= sy1 / kSubCells; ++cy)
    for (int cx = sx0 / kSubCells; cx <= sx1 / kSubCells; ++cx) {
      const Cell& cell = cells_[static_cast<size_t>(cy) * side_ + cx];
      if (cell.occupied == 0 || cell.farthest < nearestCode) continue;
      // Its occupied sub-cells inside the footprint's rectangle, then against the outline. A
      // sub-cell's receiver may be nearer the light than the cell's farthest: a bound, still exact.
      for (int sy = std::max(sy0, cy * kSubCells); sy <= std::min(sy1, cy * kSubCells + kSubCells - 1); ++sy)
        for (int sx = std::max(sx0, cx * kSubCells); sx <= std::min(sx1, cx * kSubCells + kSubCells - 1); ++sx)
          if ((cell.occupied >> (kSubCells * (sy % kSubCells) + sx % kSubCells) & 1u) != 0 && meetsOutline(sx, sy)) return true;
    }
  return false;
}

}  // namespace forest::shadows
