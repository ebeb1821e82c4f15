#pragma once
// Pass 4b of the frame (thesis §6.3, §9.4.2): the depth-aware eye-space blur of the shadow term,
// separable, its radius shrinking with depth. At full resolution this pass is the horizontal half
// and the vertical half runs inside the lighting pass (shaders/blur_taps.frag is linked into both),
// saving one full-screen pass; with the term at half resolution both halves run here, on a quarter
// of the pixels, and lighting upsamples the result (shaders/term_upsample.frag).
#include <array>
#include <map>
#include <optional>
#include <string>
#include <tuple>

#include "forest/gl/objects.hpp"
#include "forest/gl/shader.hpp"
#include "forest/render/frame.hpp"
#include "frame_block_buffer.hpp"
#include "fullscreen_triangle.hpp"

namespace forest::render {

// The most taps each side any pixel's kernel takes (shaders/blur_taps.frag: σ largest up to the
// reference depth) for a blur of `radius` image pixels on a term at `scale` pixels per texel — the
// compile-time bound of its loop (BLUR_TAPS), so that llvmpipe unrolls it (a loop bound read per
// pixel cost the half-resolution blur a third of its time). Pixels that take fewer weigh the rest 0.
inline constexpr int kMaxBlurTaps = 16;  // blur_taps.frag's cap (FrameSettings::blurRadius ≤ 16)
int blurTapsBound(double radius, int scale);
std::string blurTapsDefine(int taps);  // "#define BLUR_TAPS n\n"

class BlurPass {
 public:
  BlurPass() = default;
  // The term blurred horizontally (`term` at full resolution, `scale` 1), or both ways (at half
  // resolution, `scale` 2), for the lighting pass. The radii come from the frame block (in image
  // pixels; blur_taps.frag scales them to the term's). Runs only with the blur on.
  // At half resolution `blockDepth` (ShadowTermPass::blockDepth) limits both halves to the blocks
  // the lighting reads, as it limits the term.
  const gl::Texture& run(const gl::Texture& term, int scale, int taps, const gl::Texture* blockDepth, const FrameBlockBuffer& frameBlock);
  // Compiles the programs run() will use now (before any pass is timed).
  void prepare(int scale, int taps) {
    program(taps, false, scale > 1);
    if (scale > 1) program(taps, true, true);
  }

 private:
  // For the term at full and at half resolution (made on first use): the horizontal half's
  // image, and at half resolution the vertical half's.
  struct Images {
    PassImage horizontal;
    std::optional<PassImage> vertical;
  };
  std::array<std::optional<Images>, 2> images_;
  // Per tap bound: the horizontal and the vertical half's programs (compiled on first use).
  const gl::Program& program(int taps, bool vertical, bool halfResolution);
  std::map<std::tuple<int, bool, bool>, gl::Program> programs_;
  FullScreenTriangle triangle_;
};

}  // namespace forest::render
