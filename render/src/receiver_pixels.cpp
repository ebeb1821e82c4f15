#include "receiver_pixels.hpp"

#include <algorithm>
#include <bit>
#include <cmath>

namespace forest::render {

void ReceiverPixels::read(const GBuffer& gbuffer, int width, int height, const Camera& camera) {
  const size_t pixels = static_cast<size_t>(width) * height;
  surface_.resize(pixels);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  // The whole surface (shaders/gbuffer.frag): eye depth, albedo with the sun-facing flag, the
  // object ID (ImageVisibility::recordFromPixels).
  glGetTextureImage(gbuffer.surface.id(), 0, GL_RGBA_INTEGER, GL_UNSIGNED_INT,
                    static_cast<GLsizei>(pixels * sizeof(glm::uvec4)), surface_.data());
  // The pixel centre's ray: eye depth z → camera position + z · (forward + x tan(fovx/2) right + y tan(fovy/2) up).
  const double tanY = std::tan(0.5 * camera.fovy), tanX = tanY * camera.aspect;
  rays_ = {camera.position, camera.forward(), camera.right(), camera.up()};
  columns_.resize(static_cast<size_t>(width));  // the pixel loops divide nothing
  for (int x = 0; x < width; ++x) columns_[static_cast<size_t>(x)] = static_cast<float>((2.0 * (x + 0.5) / width - 1.0) * tanX);
  rows_.resize(static_cast<size_t>(height));
  for (int y = 0; y < height; ++y) rows_[static_cast<size_t>(y)] = static_cast<float>((2.0 * (y + 0.5) / height - 1.0) * tanY);
}

void ReceiverPixels::rowDepths(int y, std::span<float> depths) const {
  const glm::uvec4* row = surface_.data() + static_cast<size_t>(y) * columns_.size();
  const size_t count = std::min(depths.size(), columns_.size());
  for (size_t x = 0; x < count; ++x) {
    const float z = std::bit_cast<float>(row[x].x);  // 0: sky, the cleared surface
    // The lookup forces the term to 0 where the geometric normal faces away from the sun: the
    // albedo's alpha byte, 255 where it faces the sun, 0 where not (shaders/gbuffer.frag).
    depths[x] = (row[x].y >> 24) >= 128 ? z : 0.0f;
  }
}

}  // namespace forest::render
