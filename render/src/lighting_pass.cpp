#include "lighting_pass.hpp"

#include "shadow_term_pass.hpp"

namespace forest::render {

LightingPass::LightingPass(int width, int height)
    : width_(width), height_(height), usedTerm_(GL_RG16F, width, height), color_(GL_RGBA8, width, height),
      lookup_{ShadowLookupPrograms({"lighting.frag", "display_gamma.frag"}),
              ShadowLookupPrograms({"lighting.frag", "display_gamma.frag"}, "#define HAZE\n")} {
  framebuffer_.attach(GL_COLOR_ATTACHMENT0, color_);
  framebuffer_.attach(GL_COLOR_ATTACHMENT1, usedTerm_);
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
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  if (term) {
    glBindTextureUnit(5, gbuffer.surface.id());  // shaders/gbuffer_read.frag
    glBindTextureUnit(4, term->id());
  } else {
    bindShadowLookupInputs(gbuffer, shadowMap);
  }
  triangle_.draw(program(term != nullptr, shape, haze));
  for (GLuint unit = 0; unit < 7; ++unit) glBindTextureUnit(unit, 0);
  glEnable(GL_DEPTH_TEST);
  glEnable(GL_CULL_FACE);
}

}  // namespace forest::render
