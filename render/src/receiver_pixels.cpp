#include "receiver_pixels.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <thread>

namespace forest::render {

void runInParallel(int count, const std::function<void(int)>& work) {
  std::vector<std::jthread> threads;
  threads.reserve(static_cast<size_t>(std::max(0, count - 1)));
  for (int i = 1; i < count; ++i) threads.emplace_back(work, i);
  if (count > 0) work(0);
}  // the jthreads join here

int receiverBands() { return std::clamp(static_cast<int>(std::thread::hardware_concurrency()), 1, 8); }

void ReceiverPixels::read(const GBuffer& gbuffer, int width, int height, const Camera& camera) {
  const size_t pixels = static_cast<size_t>(width) * height;
  surface_.resize(pixels);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  // The surface's x and y (shaders/gbuffer.frag): eye depth, and albedo with the sun-facing flag.
  glGetTextureImage(gbuffer.surface.id(), 0, GL_RG_INTEGER, GL_UNSIGNED_INT,
                    static_cast<GLsizei>(pixels * sizeof(glm::uvec2)), surface_.data());
  // The pixel centre's ray: eye depth z → camera position + z · (forward + x tan(fovx/2) right + y tan(fovy/2) up).
  const double tanY = std::tan(0.5 * camera.fovy), tanX = tanY * camera.aspect;
  rays_ = {camera.position, camera.forward(), camera.right(), camera.up()};
  columns_.resize(static_cast<size_t>(width));  // each column's x offset, so the pixel loop divides nothing
  for (int x = 0; x < width; ++x) columns_[static_cast<size_t>(x)] = static_cast<float>((2.0 * (x + 0.5) / width - 1.0) * tanX);
  const int bands = std::min(receiverBands(), height);
  bands_.resize(static_cast<size_t>(bands));
  runInParallel(bands, [&](int band) {
    std::vector<shadows::EyePoint>& points = bands_[static_cast<size_t>(band)];
    points.clear();
    points.reserve(static_cast<size_t>(height / bands + 1) * width);
    for (int y = band; y < height; y += bands) {  // rows dealt in turn: the ground and the sky shared alike
      const float sy = static_cast<float>((2.0 * (y + 0.5) / height - 1.0) * tanY);
      for (int x = 0; x < width; ++x) {
        const glm::uvec2 s = surface_[static_cast<size_t>(y) * width + x];
        const float z = std::bit_cast<float>(s.x);
        if (!(z > 0.0f)) continue;  // sky: the cleared surface
        // The lookup forces the term to 0 where the geometric normal faces away from the sun: the
        // albedo's alpha byte, 255 where it faces the sun, 0 where not (shaders/gbuffer.frag).
        if ((s.y >> 24) < 128) continue;
        points.push_back({columns_[static_cast<size_t>(x)], sy, z});
      }
    }
  });
}

}  // namespace forest::render
