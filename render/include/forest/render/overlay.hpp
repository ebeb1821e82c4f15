#pragma once
// Images over the bound framebuffer — the window mode's stats line and help — blended by their
// alpha. Positions are pixels from the top-left corner, x right, y down.
#include <glm/glm.hpp>

#include "forest/core/image.hpp"
#include "forest/gl/objects.hpp"
#include "forest/gl/shader.hpp"

namespace forest::render {

class ImageOverlay {
 public:
  ImageOverlay();  // needs a current GL context

  // Draws `image` (4 channels, top row first) at `topLeft` into the bound framebuffer of the given size.
  void draw(const Image8& image, glm::ivec2 topLeft, int framebufferWidth, int framebufferHeight);

 private:
  gl::Program program_;
  gl::VertexArray vertexArray_;
  gl::Texture texture_;
};

}  // namespace forest::render
