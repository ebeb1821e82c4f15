#pragma once
// The reference frame: a fixed GL workload that `forest budget` times on the machine it runs on, so
// that a budget can state its limits in reference frames instead of milliseconds and one file
// serves a laptop, CI and a 2-core software renderer. It does what a frame of the engine does,
// without any of the engine's code (an engine that gets slower still shows in its ratio): a
// 256 × 256-cell heightfield (131 072 triangles, depth-tested) and three full-screen passes of 16
// texel reads each, at the run's size, timed from the first call to glFinish.
#include <array>

#include "forest/gl/objects.hpp"
#include "forest/gl/shader.hpp"

namespace forest::app {

class ReferenceFrame {
 public:
  ReferenceFrame(int width, int height);  // needs a current GL context
  // Draws it once and returns its time in milliseconds (glFinish before and after). Leaves the
  // state the engine's passes set for themselves as they expect it (depth test GL_GREATER with
  // clear depth 0, back faces culled, no scissor or blending, the default framebuffer bound).
  double timeOnceMs();

 private:
  int width_, height_;
  gl::Program mesh_, pass_;
  std::array<gl::Texture, 2> colour_;
  gl::Texture depth_;
  std::array<gl::Framebuffer, 2> target_;
  gl::VertexArray noBuffers_;
};

// The median over `repeats` timings (after two untimed ones), in milliseconds.
double measureReferenceFrameMs(int width, int height, int repeats = 9);

}  // namespace forest::app
