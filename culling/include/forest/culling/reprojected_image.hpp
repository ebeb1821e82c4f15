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
// an object without a sample (a finite, positive depth) keeps its flag. Samples of moving objects are where the object was:
// a guess, as every other.
// Measured (forest bench culling, 2026-12-05): of the trees hidden now that showed the frame before
// on the thesis walk at 10 201 trees, 125 of 146 guessed, 29 guesses wrong (visible now); eye
// triangles 1.232 → 1.192 of the oracle's; on the default forest's ground and canopy paths within
// 0.01 either way, 1–2% more queries. The samples are the image's eye depths and objects along
// its pixels' rays (SampledImage), projected a row at a time without branches: 0.43 ms for the
// 120 k samples of an 800 × 600 image (AVX2), 0.8 ms of a thesis-walk frame with the grid's clear
// and the test.
#include <glm/glm.hpp>

#include <cstdint>
#include <span>
#include <vector>

#include "forest/core/camera.hpp"

namespace forest::culling {

// The last image's samples, every ReprojectedImage::kSampleStride-th pixel of every such row: a
// grid of columns.size() × rows.size() samples, each its eye depth (along the last view's forward
// axis) and its object + 1 (0: none, the sky). Sample (i, j)'s surface point is
//   eye + depths[k] · (forward + rows[j] · up + columns[i] · right),  k = j · columns.size() + i,
// the ray at eye depth 1 through its pixel (ReceiverPixels' rays).
struct SampledImage {
  glm::dvec3 eye{0.0}, forward{0.0, 0.0, -1.0}, up{0.0, 1.0, 0.0}, right{1.0, 0.0, 0.0};
  std::vector<double> columns, rows;
  std::vector<float> depths;
  std::vector<std::uint32_t> objects;
  // Sets the rays of `camera` for an image of pixelWidth × pixelHeight pixels, sampled at every
  // kSampleStride-th pixel from pixel 0 on (pixel centres), and sizes the samples, all none.
  void reset(const Camera& camera, int pixelWidth, int pixelHeight);
};

class ReprojectedImage {
 public:
  // The samples: every kSampleStride-th pixel of every kSampleStride-th row (the grid then has
  // one cell per sample where nothing moved).
  static constexpr int kSampleStride = 2;
  // Starts the next view: a grid of gridWidth × gridHeight cells over its image. The candidates
  // are the objects o ≥ firstCandidate with shown[o] nonzero (the others' samples only hide).
  void begin(const Camera& next, int gridWidth, int gridHeight, std::span<const std::uint8_t> shown, std::size_t firstCandidate);
  // Moves the last image's samples into the next view; each cell keeps the nearest (eye depth
  // along the next view's forward axis). Samples of objects ≥ shown.size(), and those whose depth
  // is not finite and positive, are ignored (not a sample).
  void splat(const SampledImage& image);
  // Clears the flag in `shown` (begin's) of each candidate that has a sample and none of them
  // showing. Returns how many were cleared.
  int clearHidden(std::span<std::uint8_t> shown);

 private:
  glm::dmat4 viewProjection_{1.0};
  double near_ = 0.1;
  int width_ = 0, height_ = 0;
  std::vector<std::uint64_t> cells_;    // (eye depth's float bits << 32) | object + 1; all ones: empty
  // Per object: 0 not a candidate; 1 a candidate; 2 one with a sample; 3 one with a sample that shows.
  std::vector<std::uint8_t> state_;
  std::vector<std::uint32_t> rowCells_, rowDepthBits_;  // splat's: where a row's samples land, and their depths
};

}  // namespace forest::culling
