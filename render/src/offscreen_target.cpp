#include "forest/render/offscreen_target.hpp"

namespace forest::render {

OffscreenTarget::OffscreenTarget(int width, int height)
    : color_(GL_RGBA8, width, height), depth_(GL_DEPTH_COMPONENT32F, width, height) {
  framebuffer_.attach(GL_COLOR_ATTACHMENT0, color_);
  framebuffer_.attach(GL_DEPTH_ATTACHMENT, depth_);
  framebuffer_.checkComplete("OffscreenTarget");
}

void OffscreenTarget::bind() const {
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_.id());
  glViewport(0, 0, width(), height());
}

Image8 OffscreenTarget::readColor() const {
  Image8 image(width(), height(), 4);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glGetTextureImage(color_.id(), 0, GL_RGBA, GL_UNSIGNED_BYTE, static_cast<GLsizei>(image.pixels.size()),
                    image.pixels.data());
  flipRows(image);
  return image;
}

ImageF OffscreenTarget::readDepth() const {
  ImageF image(width(), height(), 1);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glGetTextureImage(depth_.id(), 0, GL_DEPTH_COMPONENT, GL_FLOAT,
                    static_cast<GLsizei>(image.pixels.size() * sizeof(float)), image.pixels.data());
  flipRows(image);
  return image;
}

}  // namespace forest::render
