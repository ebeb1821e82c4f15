#include "receiver_pixels.hpp"

#include <cmath>

namespace forest::render {

void ReceiverPixels::read(const GBuffer& gbuffer, int width, int height, const Camera& camera) {
  const size_t pixels = static_cast<size_t>(width) * height;
  depth_.resize(pixels);
  albedo_.resize(4 * pixels);
  points_.reserve(pixels);
  points_.clear();
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glGetTextureImage(gbuffer.depth.id(), 0, GL_DEPTH_COMPONENT, GL_FLOAT, static_cast<GLsizei>(pixels * sizeof(float)), depth_.data());
  glGetTextureImage(gbuffer.albedo.id(), 0, GL_RGBA, GL_UNSIGNED_BYTE, static_cast<GLsizei>(4 * pixels), albedo_.data());
  // The pixel centre's ray: eye depth z → camera position + z · (forward + x tan(fovx/2) right + y tan(fovy/2) up).
  const double tanY = std::tan(0.5 * camera.fovy), tanX = tanY * camera.aspect;
  rays_ = {camera.position, camera.forward(), camera.right(), camera.up()};
  for (int y = 0; y < height; ++y) {
    const double sy = (2.0 * (y + 0.5) / height - 1.0) * tanY;
    for (int x = 0; x < width; ++x) {
      const size_t i = static_cast<size_t>(y) * width + x;
      if (!(depth_[i] > 0.0f)) continue;  // sky: the cleared far depth
      // The lookup forces the term to 0 where the geometric normal faces away from the sun: the
      // albedo's alpha, 255 where it faces the sun, 0 where not (shaders/gbuffer.frag).
      if (albedo_[4 * i + 3] < 128) continue;
      const double z = camera.eyeDepthOfReversedZ(depth_[i]);
      const double sx = (2.0 * (x + 0.5) / width - 1.0) * tanX;
      points_.push_back({sx, sy, z});
    }
  }
}

}  // namespace forest::render
