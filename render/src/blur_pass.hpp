#pragma once
// Pass 4b of the frame (thesis §6.3, §9.4.2): the depth-aware eye-space blur of the shadow term,
// separable, its radius shrinking with depth. This pass is the horizontal half; the vertical half
// runs inside the lighting pass (shaders/blur_taps.frag is linked into both), saving one
// full-screen pass.
#include "forest/gl/objects.hpp"
#include "forest/gl/shader.hpp"
#include "forest/render/frame.hpp"
#include "frame_block_buffer.hpp"
#include "fullscreen_triangle.hpp"

namespace forest::render {

class BlurPass {
 public:
  BlurPass(int width, int height);
  // The horizontally blurred term, which the lighting pass reads. The radii come from the frame
  // block. Runs only with the blur on.
  const gl::Texture& run(const gl::Texture& term, const FrameBlockBuffer& frameBlock);

 private:
  gl::Texture horizontal_;
  gl::Framebuffer framebuffer_;
  gl::Program program_;
  FullScreenTriangle triangle_;
};

}  // namespace forest::render
