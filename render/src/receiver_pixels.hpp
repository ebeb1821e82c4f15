#pragma once
// The visible receiver pixels of a frame for CasterSelection::ReceiverPixels: the G-buffer surface's
// eye depth and albedo (its alpha: whether the geometric normal faces the sun) read back (the CPU
// waits for the geometry pass). A pixel that faces the sun — one whose shadow term is looked up
// (shaders/shadow_lookup.frag) — is a receiver at its eye depth along its ray; the receiver mask
// takes them row by row (shadows::ReceiverMask::addEyeRow), the rows split into bands, one per
// hardware thread (ShadowSetupPass::fillReceiverMask): a software rasteriser's threads sit idle
// while the CPU works here. The read keeps each pixel's object ID too: ImageVisibility records
// from it what showed, so that the lighting pass need not. Storage is kept from frame to frame.
#include <glm/glm.hpp>

#include <span>
#include <vector>

#include "forest/core/camera.hpp"
#include "forest/shadows/receiver_mask.hpp"
#include "geometry_pass.hpp"

namespace forest::render {

class ReceiverPixels {
 public:
  void read(const GBuffer& gbuffer, int width, int height, const Camera& camera);
  int width() const { return static_cast<int>(columns_.size()); }
  int height() const { return static_cast<int>(rows_.size()); }
  // Row y's receivers (y = 0 at the bottom): the eye depth of each sun-facing pixel, 0 where there
  // is none (sky, or a surface turned from the sun). `depths` holds width() floats.
  void rowDepths(int y, std::span<float> depths) const;
  // Pixel (x, y)'s G-buffer surface (shaders/gbuffer.frag: x eye depth bits, 0 for the sky; w the
  // object ID, 0 for the sky), row y = 0 at the bottom.
  const glm::uvec4& surface(int x, int y) const { return surface_[static_cast<size_t>(y) * columns_.size() + static_cast<size_t>(x)]; }
  // The pixel centres' offsets at eye depth 1: along right per column, along up per row; with
  // rays() a pixel's receiver is eye + z · (forward + column · right + row · up).
  std::span<const float> columns() const { return columns_; }
  float row(int y) const { return rows_[static_cast<size_t>(y)]; }
  const shadows::EyeRays& rays() const { return rays_; }

 private:
  std::vector<glm::uvec4> surface_;  // the G-buffer surface (shaders/gbuffer.frag)
  std::vector<float> columns_, rows_;
  shadows::EyeRays rays_{};
};

}  // namespace forest::render
