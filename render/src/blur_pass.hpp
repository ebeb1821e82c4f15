#pragma once
// Pass 4b of the frame (thesis §6.3, §9.4.2): the depth-aware eye-space blur of the shadow term,
// separable, its radius shrinking with depth. This pass is the horizontal half; the vertical half
// runs inside the lighting pass (shaders/blur_taps.frag is linked into both), saving one
// full-screen pass.
#include "forest/gl/objects.hpp"
#include "forest/gl/shader.hpp"
#include "forest/render/frame.hpp"
#include "fullscreen_triangle.hpp"

namespace forest::render {

// The blur averages only samples whose eye depth is within this share of the centre's (no bleeding
// across silhouettes; a sloped surface's depth changes less than this over 16 pixels).
constexpr double kBlurDepthTolerance = 0.05;

// The blur's uniforms, the same in both halves.
void setBlurUniforms(const gl::Program& program, const FrameSettings& settings);

class BlurPass {
 public:
  BlurPass(int width, int height);
  // The term the lighting pass reads: the horizontally blurred term, or `term` itself when the
  // blur is off (then this pass draws nothing).
  const gl::Texture& run(const gl::Texture& term, const FrameSettings& settings);

 private:
  gl::Texture horizontal_;
  gl::Framebuffer framebuffer_;
  gl::Program program_;
  FullScreenTriangle triangle_;
};

}  // namespace forest::render
