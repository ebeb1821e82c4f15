#pragma once
// The visible receiver pixels of a frame for CasterSelection::ReceiverPixels: the G-buffer's depth
// and albedo (its alpha: whether the geometric normal faces the sun) read back (the CPU waits for
// the geometry pass), and for every pixel that faces the sun — the pixels whose shadow term is
// looked up (shaders/shadow_lookup.frag) — its world position and eye depth. Storage is kept from
// frame to frame.
#include <glm/glm.hpp>

#include <cstdint>
#include <span>
#include <vector>

#include "forest/core/camera.hpp"
#include "geometry_pass.hpp"

namespace forest::render {

class ReceiverPixels {
 public:
  void read(const GBuffer& gbuffer, int width, int height, const Camera& camera);
  // xyz: world position at the pixel's centre; w: eye depth (m).
  std::span<const glm::dvec4> points() const { return points_; }

 private:
  std::vector<float> depth_;
  std::vector<std::uint8_t> albedo_;  // RGBA
  std::vector<glm::dvec4> points_;
};

}  // namespace forest::render
