#pragma once
// The visible receiver pixels of a frame for CasterSelection::ReceiverPixels: the G-buffer surface's
// eye depth and albedo (its alpha: whether the geometric normal faces the sun) read back (the CPU
// waits for the geometry pass), and for every pixel that faces the sun — the pixels whose shadow term is
// looked up (shaders/shadow_lookup.frag) — its ray's offsets and eye depth, which place it from the
// eye (shadows::ReceiverMask::addEyePoints). Storage is kept from frame to frame.
#include <glm/glm.hpp>

#include <cstdint>
#include <span>
#include <vector>

#include "forest/core/camera.hpp"
#include "forest/shadows/receiver_mask.hpp"
#include "geometry_pass.hpp"

namespace forest::render {

class ReceiverPixels {
 public:
  void read(const GBuffer& gbuffer, int width, int height, const Camera& camera);
  // The sun-facing pixels' centres: eye + z · (forward + x · right + y · up) with rays().
  std::span<const shadows::EyePoint> points() const { return points_; }
  const shadows::EyeRays& rays() const { return rays_; }

 private:
  std::vector<glm::uvec2> surface_;  // the G-buffer surface's x and y (shaders/gbuffer.frag)
  std::vector<shadows::EyePoint> points_;
  shadows::EyeRays rays_{};
};

}  // namespace forest::render
