#include "blur_pass.hpp"

namespace forest::render {

BlurPass::BlurPass(int width, int height)
    : horizontal_(GL_RG16F, width, height),
      program_(loadFullScreenProgram({"shadow_blur.frag", "blur_taps.frag"})) {
  framebuffer_.attach(GL_COLOR_ATTACHMENT0, horizontal_);
  framebuffer_.checkComplete("blur");
  glTextureParameteri(horizontal_.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(horizontal_.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
}

const gl::Texture& BlurPass::run(const gl::Texture& term, const FrameBlockBuffer& frameBlock) {
  frameBlock.bind();
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_.id());
  glBindTextureUnit(0, term.id());
  triangle_.draw(program_);
  return horizontal_;
}

}  // namespace forest::render
