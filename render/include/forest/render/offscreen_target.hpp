#pragma once
// A colour + depth render target (RGBA8 colour, 32-bit float depth for reversed-Z).
#include "forest/core/image.hpp"
#include "forest/gl/objects.hpp"

namespace forest::render {

class OffscreenTarget {
 public:
  OffscreenTarget(int width, int height);

  int width() const { return color_.width(); }
  int height() const { return color_.height(); }
  const gl::Framebuffer& framebuffer() const { return framebuffer_; }
  const gl::Texture& color() const { return color_; }
  const gl::Texture& depth() const { return depth_; }

  // Binds the framebuffer and sets the viewport to the whole target.
  void bind() const;
  // Colour as RGBA8, top row first.
  Image8 readColor() const;
  // Depth (reversed-Z: 1 = near plane, 0 = far/cleared), top row first.
  ImageF readDepth() const;

 private:
  gl::Texture color_;
  gl::Texture depth_;
  gl::Framebuffer framebuffer_;
};

}  // namespace forest::render
