#include "forest/shadows/receiver_mask.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>

#include "forest/core/error.hpp"

namespace forest::shadows {

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
  cells_ = cells;
  receivers_ = 0;
  everywhere_ = false;
  farthest_.assign(static_cast<size_t>(cells) * cells, -std::numeric_limits<float>::infinity());
}

double ReceiverMask::depthOf(const dvec3& world, const dvec4& clip) const {
  return linearDepth_ ? glm::dot(worldToLightDepth_, dvec4(world, 1.0)) : clip.z / clip.w;
}

// Inlined: a frame calls these once per sun-facing pixel.
[[gnu::always_inline]] inline int ReceiverMask::cellOf(double ndc) const {
  // Clamped first, then truncated: the same as floor then clamp, without a call to floor (no
  // SSE4.1 rounding instruction in the baseline x86-64 build).
  return static_cast<int>(std::clamp((ndc + 1.0) * 0.5 * cells_, 0.0, cells_ - 1.0));
}

[[gnu::always_inline]] inline void ReceiverMask::addClip(const dvec4& h, double invW, double depth) {
  const double x = h.x * invW, y = h.y * invW;
  if (!(h.w > 0.0) || !std::isfinite(x) || !std::isfinite(y) || !std::isfinite(depth)) {
    everywhere_ = true;  // a receiver the map cannot place: every caster may shadow it
    return;
  }
  ++receivers_;
  float& cell = farthest_[static_cast<size_t>(cellOf(y)) * cells_ + cellOf(x)];
  // Rounded up, without a branch (a frame adds one point per pixel, and whether a point raises its
  // cell is a coin toss to the branch predictor): |depth| grown by 2⁻²² of itself rounds to a
  // float no nearer the light than the point (round to nearest moves it by at most 2⁻²⁴).
  constexpr double kUp = 1.0 + 0x1p-22, kDown = 1.0 - 0x1p-22;
  const float rounded = static_cast<float>(depth * (depth >= 0.0 ? kUp : kDown));
  cell = std::max(cell, rounded);
}

void ReceiverMask::add(const dvec3& world) {
  const dvec4 h = worldToShadowClip_ * dvec4(world, 1.0);
  addClip(h, 1.0 / h.w, depthOf(world, h));
}

void ReceiverMask::addEyeRow(const EyeRays& rays, float row, std::span<const float> columns, std::span<const float> depths,
                             double zMin, double zMax) {
  // M (eye + z (f + y u + x r)) = M eye + z (M (f + y u) + x M r): the map's clip position, and
  // likewise tsm's linear light depth, is affine in z·(1, x) along a row.
  const dvec3 rowRay = rays.forward + static_cast<double>(row) * rays.up;
  const dvec4 origin = worldToShadowClip_ * dvec4(rays.eye, 1.0);
  const dvec4 base = worldToShadowClip_ * dvec4(rowRay, 0.0);
  const dvec4 right = worldToShadowClip_ * dvec4(rays.right, 0.0);
  const double depthOrigin = glm::dot(worldToLightDepth_, dvec4(rays.eye, 1.0));
  const double depthBase = glm::dot(worldToLightDepth_, dvec4(rowRay, 0.0));
  const double depthRight = glm::dot(worldToLightDepth_, dvec4(rays.right, 0.0));
  const size_t count = std::min(columns.size(), depths.size());
  for (size_t i = 0; i < count; ++i) {
    const double z = depths[i];
    if (!(z >= zMin && z <= zMax)) continue;
    const double x = columns[i];
    const dvec4 h = origin + z * (base + x * right);
    const double invW = 1.0 / h.w;  // one division per point: clip z / w is h.z · invW
    const double depth = linearDepth_ ? depthOrigin + z * (depthBase + x * depthRight) : h.z * invW;
    addClip(h, invW, depth);
  }
}

void ReceiverMask::merge(const ReceiverMask& other) {
  if (other.cells_ != cells_ || other.mapSize_ != mapSize_ || other.worldToShadowClip_ != worldToShadowClip_)
    throw Error("ReceiverMask::merge: the masks are of different maps or cells");
  receivers_ += other.receivers_;
  everywhere_ = everywhere_ || other.everywhere_;
  for (size_t i = 0; i < farthest_.size(); ++i) farthest_[i] = std::max(farthest_[i], other.farthest_[i]);
}

bool ReceiverMask::mayShadow(const Aabb& caster, double reachTexels) const {
  if (everywhere_) return true;
  if (cells_ == 0) return false;
  // The box's footprint in the map (x, y) and its nearest depth: over a box, a projective map's
  // x/w, y/w and depth are extreme at corners when w > 0 at all of them (w is affine).
  double x0 = std::numeric_limits<double>::infinity(), x1 = -x0, y0 = x0, y1 = -x0, nearest = x0;
  for (int c = 0; c < 8; ++c) {
    const dvec3 p = caster.corner(c);
    const dvec4 h = worldToShadowClip_ * dvec4(p, 1.0);
    if (!(h.w > 0.0)) return true;
    const double x = h.x / h.w, y = h.y / h.w, z = depthOf(p, h);
    x0 = std::min(x0, x);
    x1 = std::max(x1, x);
    y0 = std::min(y0, y);
    y1 = std::max(y1, y);
    nearest = std::min(nearest, z);
  }
  // Grown by the reach, in map units (2 / mapSize per texel).
  const double grow = reachTexels * 2.0 / mapSize_;
  const int cx0 = cellOf(x0 - grow), cx1 = cellOf(x1 + grow), cy0 = cellOf(y0 - grow), cy1 = cellOf(y1 + grow);
  for (int cy = cy0; cy <= cy1; ++cy)
    for (int cx = cx0; cx <= cx1; ++cx)
      if (static_cast<double>(farthest_[static_cast<size_t>(cy) * cells_ + cx]) >= nearest - kDepthTolerance) return true;
  return false;
}

}  // namespace forest::shadows
