#pragma once
// Pass 5 of the frame (thesis §6.2, DESIGN §4): Phong lighting from the G-buffer with a weak
// global ambient, the shadow term (the blur's vertical half when the blur is on, the lookup itself
// when it is off), fog and the sky colour. Targets: the lit colour (RGBA8) and, when asked, the term
// it used (RG16F).
#include <glm/glm.hpp>

#include <array>
#include <optional>
#include <string>

#include "forest/core/scene.hpp"
#include "forest/gl/objects.hpp"
#include "forest/gl/shader.hpp"
#include "forest/render/frame.hpp"
#include "frame_block_buffer.hpp"
#include "fullscreen_triangle.hpp"
#include "geometry_pass.hpp"
#include "shadow_term_pass.hpp"

namespace forest::render {

class LightingPass {
 public:
  LightingPass(int width, int height);
  // With the blur on, `term` is the horizontally blurred shadow term; with it off (null), the
  // term is looked up in `shadowMap`. The sun, sky, fog and blur come from the frame block;
  // `haze`: whether its haze density is above 0. `keepTerm`: also
  // write the term used into usedTerm(). `record`: record what shows (ImageVisibility::beginRecord
  // has bound its buffer; a program that can write it is slower on llvmpipe even when it does not).
  void run(const GBuffer& gbuffer, const gl::Texture* term, const gl::Texture& shadowMap, const ShadowLookupShape& shape,
           const FrameBlockBuffer& frameBlock, bool haze, bool keepTerm, bool record);
  // Compiles the program run() will use now (before any pass is timed).
  void prepare(bool blurred, const ShadowLookupShape& shape, bool haze, bool record) { program(blurred, shape, haze, record); }

  const gl::Texture& color() const { return color_; }
  const gl::Texture& usedTerm() const { return usedTerm_; }
  const gl::Framebuffer& framebuffer() const { return framebuffer_; }

 private:
  int width_, height_;
  gl::Texture usedTerm_, color_;
  gl::Framebuffer framebuffer_;
  const gl::Program& program(bool blurred, const ShadowLookupShape& shape, bool haze, bool record);
  // Indexed by haze + 2 record (HAZE, RECORD_SHOWN): the programs taking the term from the blur's
  // horizontal pass, and those looking it up here (compiled on first use).
  static std::string defines(bool haze, bool record);
  std::array<std::optional<gl::Program>, 4> blurred_;
  std::array<std::optional<ShadowLookupPrograms>, 4> lookup_;
  FullScreenTriangle triangle_;
};

}  // namespace forest::render
