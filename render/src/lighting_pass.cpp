#include "lighting_pass.hpp"

#include "shadow_term_pass.hpp"

namespace forest::render {

LightingPass::LightingPass(int width, int height)
    : width_(width), height_(height), usedTerm_(GL_RG16F, width, height), color_(GL_RGBA8, width, height) {
  framebuffer_.attach(GL_COLOR_ATTACHMENT0, color_);
  framebuffer_.attach(GL_COLOR_ATTACHMENT1, usedTerm_);
  framebuffer_.checkComplete("colour");
  glTextureParameteri(usedTerm_.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(usedTerm_.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
}

std::string LightingPass::defines(bool haze, bool record) {
  return std::string(haze ? "#define HAZE\n" : "") + (record ? "#define RECORD_SHOWN\n" : "");
}

const gl::Program& LightingPass::program(bool blurred, const ShadowLookupShape& shape, bool haze, bool record) {
  const std::size_t variant = static_cast<std::size_t>(haze) + 2 * static_cast<std::size_t>(record);
  if (!blurred) {
    std::optional<ShadowLookupPrograms>& programs = lookup_[variant];
    if (!programs) programs.emplace(std::vector<std::string>{"lighting.frag", "display_gamma.frag"}, defines(haze, record));
    return programs->get(shape);
  }
  std::optional<gl::Program>& program = blurred_[variant];
  if (!program)
    program = loadFullScreenProgram({"lighting.frag", "display_gamma.frag", "blur_taps.frag", "gbuffer_read.frag"},
                                    "#define BLURRED_TERM\n" + defines(haze, record));
  return *program;
}

void LightingPass::run(const GBuffer& gbuffer, const gl::Texture* term, const gl::Texture& shadowMap, const ShadowLookupShape& shape,
                       const FrameBlockBuffer& frameBlock, bool haze, bool keepTerm, bool record) {
  frameBlock.bind();
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
  triangle_.draw(program(term != nullptr, shape, haze, record));
  for (GLuint unit = 0; unit < 7; ++unit) glBindTextureUnit(unit, 0);
  glEnable(GL_DEPTH_TEST);
  glEnable(GL_CULL_FACE);
}

}  // namespace forest::render
