#include "forest/render/overlay.hpp"

#include <fmt/format.h>

#include "forest/core/error.hpp"

namespace forest::render {

ImageOverlay::ImageOverlay() : program_(gl::loadProgram({"overlay.vert", "overlay.frag"})) {}

void ImageOverlay::draw(const Image8& image, glm::ivec2 topLeft, int framebufferWidth, int framebufferHeight) {
  if (image.channels != 4) throw Error(fmt::format("overlay: {} channels, expected RGBA", image.channels));
  if (image.width <= 0 || image.height <= 0) return;
  if (texture_.width() != image.width || texture_.height() != image.height) {
    texture_ = gl::Texture(GL_RGBA8, image.width, image.height);
    glTextureParameteri(texture_.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(texture_.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  }
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTextureSubImage2D(texture_.id(), 0, 0, 0, image.width, image.height, GL_RGBA, GL_UNSIGNED_BYTE, image.pixels.data());
  // Pixel rectangle → normalised device coordinates (GL's y points up).
  const glm::vec2 size(framebufferWidth, framebufferHeight);
  const glm::vec2 lo(static_cast<float>(topLeft.x), static_cast<float>(framebufferHeight - topLeft.y - image.height));
  const glm::vec2 hi = lo + glm::vec2(image.width, image.height);
  program_.use();
  program_.set("uRect", glm::vec4(2.0f * lo / size - 1.0f, 2.0f * hi / size - 1.0f));
  glBindTextureUnit(0, texture_.id());
  program_.set("uImage", 0);
  glBindVertexArray(vertexArray_.id());
  glViewport(0, 0, framebufferWidth, framebufferHeight);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  glEnable(GL_BLEND);
  glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
  glDisable(GL_BLEND);
  glBindVertexArray(0);
}

}  // namespace forest::render
