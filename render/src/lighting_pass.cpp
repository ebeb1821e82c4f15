#include "lighting_pass.hpp"

#include "shadow_term_pass.hpp"

namespace forest::render {

LightingPass::LightingPass(int width, int height, const gl::Texture& surfaceDepth)
    : width_(width), height_(height), usedTerm_(GL_RG16F, width, height), color_(GL_RGBA8, width, height),
      lookup_{ShadowLookupPrograms({"lighting.frag", "display_gamma.frag"}),
              ShadowLookupPrograms({"lighting.frag", "display_gamma.frag"}, "#define HAZE\n")},
      sky_(loadFullScreenProgram({"lighting.frag", "display_gamma.frag"}, "#define SKY_PIXELS\n")) {
  framebuffer_.attach(GL_COLOR_ATTACHMENT0, color_);
  framebuffer_.attach(GL_COLOR_ATTACHMENT1, usedTerm_);
  framebuffer_.attach(GL_DEPTH_ATTACHMENT, surfaceDepth);
  framebuffer_.checkComplete("colour");
  glTextureParameteri(usedTerm_.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(usedTerm_.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
}

const gl::Program& LightingPass::program(bool blurred, const ShadowLookupShape& shape, bool haze) {
  if (!blurred) return lookup_[haze].get(shape);
  std::optional<gl::Program>& program = blurred_[haze];
  if (!program)
    program = loadFullScreenProgram({"lighting.frag", "display_gamma.frag", "blur_taps.frag", "gbuffer_read.frag"},
                                    std::string("#define BLURRED_TERM\n") + (haze ? "#define HAZE\n" : ""));
  return *program;
}

void LightingPass::run(const GBuffer& gbuffer, const gl::Texture* term, const gl::Texture& shadowMap, const ShadowLookupShape& shape,
                       bool haze, bool keepTerm) {
  // Without the term's target the shader's second output goes nowhere.
  const GLenum buffers[2] = {GL_COLOR_ATTACHMENT0, keepTerm ? GLenum{GL_COLOR_ATTACHMENT1} : GLenum{GL_NONE}};
  glNamedFramebufferDrawBuffers(framebuffer_.id(), 2, buffers);
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_.id());
  glViewport(0, 0, width_, height_);
  glDisable(GL_CULL_FACE);
  if (term) {
    glBindTextureUnit(5, gbuffer.surface.id());  // shaders/gbuffer_read.frag
    glBindTextureUnit(4, term->id());
  } else {
    bindShadowLookupInputs(gbuffer, shadowMap);
  }
  // The triangle lies at depth 0, the G-buffer's clear value (reversed-Z), which no drawn surface
  // keeps: the geometry pass's GL_GREATER lets no fragment at depth 0 through. So GL_LESS passes
  // exactly the pixels where something was drawn, GL_EQUAL exactly the sky; each pixel is shaded
  // once, by one of the two programs.
  glEnable(GL_DEPTH_TEST);
  glDepthMask(GL_FALSE);
  glDepthFunc(GL_LESS);
  triangle_.draw(program(term != nullptr, shape, haze));
  glDepthFunc(GL_EQUAL);
  triangle_.draw(sky_);
  for (GLuint unit = 0; unit < 7; ++unit) glBindTextureUnit(unit, 0);
  glDepthMask(GL_TRUE);
  glDepthFunc(GL_GREATER);  // the frame's convention (reversed-Z)
  glEnable(GL_CULL_FACE);
}

}  // namespace forest::render
