#include "shadow_term_pass.hpp"

namespace forest::render {

void bindShadowLookupInputs(const GBuffer& gbuffer, const gl::Texture& shadowMap) {
  glBindTextureUnit(5, gbuffer.depth.id());  // the bindings of shaders/shadow_lookup.frag
  glBindTextureUnit(6, gbuffer.geometricNormal.id());
  glBindTextureUnit(3, shadowMap.id());
}

ShadowTermPass::ShadowTermPass(int width, int height)
    : width_(width), height_(height), term_(GL_RG16F, width, height),
      program_(loadFullScreenProgram({"shadow_term.frag", "shadow_lookup.frag"})) {
  framebuffer_.attach(GL_COLOR_ATTACHMENT0, term_);
  framebuffer_.checkComplete("shadow term");
  glTextureParameteri(term_.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(term_.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
}

void ShadowTermPass::run(const GBuffer& gbuffer, const gl::Texture& shadowMap) {
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_.id());
  glViewport(0, 0, width_, height_);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  bindShadowLookupInputs(gbuffer, shadowMap);
  triangle_.draw(program_);
}

}  // namespace forest::render
