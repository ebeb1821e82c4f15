#pragma once
// Beyond CHC++: which objects that showed in the last image are hidden in the next view, guessed
// from the last image itself. CHC (and CHC++ §3.3) draws what was visible the frame before
// untested, so an object that a nearer one covers as the eye moves is drawn once more than it
// must be (the one-frame lag; on the thesis walk at 10 201 trees 0.64 trees a frame, half the
// excess over the exactly visible set). Its surface points and those of the objects in front of
// it are known: the last image's samples. Moved into the next view (forward reprojection, a
// z-buffer of points), an object none of whose samples is the nearest in its cell is most likely
// hidden now; the culler then asks it before it draws it, as it asks an object without a pixel
// (OcclusionCuller::setShownInLastImage). A wrong guess costs a query and a later draw, never a
// pixel: the query against this frame's depth decides.
// A sample shows where it is the nearest in its cell, unless the nearer samples on both sides of
// it (along a row, a column or a diagonal) belong to one object: then it lies in a hole that
// object's samples left as they spread apart (it came nearer, or turned), not in a gap between two
// objects. A sample that leaves the image or lies behind the next eye's near plane does not show;
// an object without a (finite) sample keeps its flag. Samples of moving objects are where the object was:
// a guess, as every other.
// Measured (forest bench culling, 2026-12-05): of the trees hidden now that showed the frame before
// on the thesis walk at 10 201 trees, 125 of 146 guessed, 29 guesses wrong (visible now); eye
// triangles 1.232 → 1.192 of the oracle's; on the default forest's ground and canopy paths within
// 0.01 either way, 1–2% more queries.
#include <glm/glm.hpp>

#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "forest/core/camera.hpp"

namespace forest::culling {

// A sample of the last image: a surface point (world space) and the object it belongs to.
struct ImageSample {
  glm::vec3 position;
  std::uint32_t object;
};

class ReprojectedImage {
 public:
  // The samples: every kSampleStride-th pixel of every kSampleStride-th row (the grid then has
  // one cell per sample where nothing moved).
  static constexpr int kSampleStride = 2;
  // Starts the next view: a grid of gridWidth × gridHeight cells over its image. The candidates
  // are the objects o ≥ firstCandidate with shown[o] nonzero (the others' samples only hide).
  void begin(const Camera& next, int gridWidth, int gridHeight, std::span<const std::uint8_t> shown, std::size_t firstCandidate);
  // Moves samples into the next view; each cell keeps the nearest (eye depth along the next
  // view's forward axis). Samples of objects ≥ shown.size() are ignored.
  void splat(std::span<const ImageSample> samples);
  // Clears the flag in `shown` (begin's) of each candidate that has a sample and none of them
  // showing. Returns how many were cleared.
  int clearHidden(std::span<std::uint8_t> shown);

 private:
  glm::dmat4 viewProjection_{1.0};
  double near_ = 0.1;
  int width_ = 0, height_ = 0;
  std::vector<std::uint64_t> cells_;    // (eye depth's float bits << 32) | object + 1; 0: empty
  // Per object: 0 not a candidate; 1 a candidate; 2 one with a sample; 3 one with a sample that shows.
  std::vector<std::uint8_t> state_;
  std::vector<std::pair<std::size_t, std::uint64_t>> witnesses_;  // per candidate's sample on the grid: its cell and key
};

}  // namespace forest::culling
