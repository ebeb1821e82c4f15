#include "forest/culling/reprojected_image.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cmath>

#include "forest/core/error.hpp"

namespace forest::culling {

namespace {
enum : std::uint8_t { kOther = 0, kCandidate = 1, kSampled = 2, kShows = 3 };
}  // namespace

void ReprojectedImage::begin(const Camera& next, int gridWidth, int gridHeight, std::span<const std::uint8_t> shown, std::size_t firstCandidate) {
  if (gridWidth < 1 || gridHeight < 1)
    throw Error(fmt::format("ReprojectedImage: a grid of {} × {} cells, expected at least 1 × 1", gridWidth, gridHeight));
  viewProjection_ = next.projection() * next.view();
  near_ = next.near;
  width_ = gridWidth;
  height_ = gridHeight;
  cells_.assign(static_cast<std::size_t>(gridWidth) * static_cast<std::size_t>(gridHeight), 0);
  state_.assign(shown.size(), kOther);
  for (std::size_t o = firstCandidate; o < shown.size(); ++o)
    if (shown[o] != 0) state_[o] = kCandidate;
  witnesses_.clear();
}

void ReprojectedImage::splat(std::span<const ImageSample> samples) {
  const std::size_t objects = state_.size();
  // Clip x, y and w of a point: rows 0, 1 and 3 of the view-projection (clip.w: the eye depth
  // along the next view's forward axis, for a perspective projection).
  const glm::dmat4 m = glm::transpose(viewProjection_);
  for (const ImageSample& s : samples) {
    if (s.object >= objects || !std::isfinite(s.position.x) || !std::isfinite(s.position.y) || !std::isfinite(s.position.z))
      continue;  // not a sample
    if (state_[s.object] == kCandidate) state_[s.object] = kSampled;
    const glm::dvec4 p(glm::dvec3(s.position), 1.0);
    const double w = glm::dot(m[3], p);
    // Behind the next eye's near plane: it cannot hide anything in front of that eye, and does
    // not show.
    if (!(w >= near_)) continue;
    // The cell of its normalised device coordinates x, y ∈ [−1, 1].
    const double cx = (glm::dot(m[0], p) / w * 0.5 + 0.5) * width_, cy = (glm::dot(m[1], p) / w * 0.5 + 0.5) * height_;
    if (!(cx >= 0.0 && cx < width_ && cy >= 0.0 && cy < height_)) continue;  // off the image (NaN too): does not show
    // A positive float's bits order as the float does: the nearest sample has the smallest key.
    const std::uint64_t key = static_cast<std::uint64_t>(std::bit_cast<std::uint32_t>(static_cast<float>(w))) << 32 | (s.object + 1u);
    const std::size_t cell = static_cast<std::size_t>(static_cast<int>(cy)) * static_cast<std::size_t>(width_) + static_cast<std::size_t>(static_cast<int>(cx));
    std::uint64_t& kept = cells_[cell];
    if (kept == 0 || key < kept) kept = key;
    if (state_[s.object] != kOther) {
      state_[s.object] = std::max<std::uint8_t>(state_[s.object], kSampled);
      witnesses_.push_back({cell, key});
    }
  }
}

int ReprojectedImage::clearHidden(std::span<std::uint8_t> shown) {
  // A sample shows where it is the nearest in its cell and the nearer samples on both sides of it
  // are not one object's: where a nearer surface's samples spread apart (it came nearer, or
  // turned), a cell between them is left without one of its samples, and what was behind it
  // shows through that hole.
  // The object (+ 1) of the sample in cell (x, y) when it is nearer than `key`'s, else 0.
  const auto nearer = [this](int x, int y, std::uint64_t key) -> std::uint64_t {
    if (x < 0 || y < 0 || x >= width_ || y >= height_) return 0;
    const std::uint64_t other = cells_[static_cast<std::size_t>(y) * static_cast<std::size_t>(width_) + static_cast<std::size_t>(x)];
    return other != 0 && other < key ? (other & 0xffffffffu) : 0;
  };
  const auto between = [&](int x0, int y0, int x1, int y1, std::uint64_t key) {
    const std::uint64_t a = nearer(x0, y0, key);
    return a != 0 && a == nearer(x1, y1, key);
  };
  for (const auto& [cell, key] : witnesses_) {
    std::uint8_t& state = state_[static_cast<std::size_t>((key & 0xffffffffu) - 1u)];
    if (state == kShows || cells_[cell] != key) continue;
    const int x = static_cast<int>(cell % static_cast<std::size_t>(width_)), y = static_cast<int>(cell / static_cast<std::size_t>(width_));
    const bool inHole = between(x - 1, y, x + 1, y, key) || between(x, y - 1, x, y + 1, key) || between(x - 1, y - 1, x + 1, y + 1, key) ||
                        between(x - 1, y + 1, x + 1, y - 1, key);
    if (!inHole) state = kShows;
  }
  int cleared = 0;
  const std::size_t end = std::min(shown.size(), state_.size());
  for (std::size_t o = 0; o < end; ++o) {
    if (state_[o] == kSampled) {
      shown[o] = 0;
      ++cleared;
    }
  }
  return cleared;
}

}  // namespace forest::culling
