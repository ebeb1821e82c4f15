#include "lighting_pass.hpp"

#include "shadow_term_pass.hpp"

namespace forest::render {

LightingPass::LightingPass(int width, int height, const GBuffer& gbuffer)
    : width_(width),
      height_(height),
      usedTerm_(GL_RG16F, width, height),
      color_(GL_RGBA8, width, height),
      sky_(loadFullScreenProgram({"sky.frag", "sky_radiance.frag", "display_gamma.frag"})) {
  framebuffer_.attach(GL_COLOR_ATTACHMENT0, color_);
  framebuffer_.attach(GL_COLOR_ATTACHMENT1, usedTerm_);
  framebuffer_.attach(GL_DEPTH_ATTACHMENT, gbuffer.depth);
  framebuffer_.checkComplete("colour");
  glTextureParameteri(usedTerm_.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(usedTerm_.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
}

LightingPass::ProgramKey LightingPass::nearHalfTermDepth(ProgramKey key) {
  key.atHalfTermDepth = true;
  return key;
}

LightingPass::ProgramKey LightingPass::beyondHalfTermDepth(ProgramKey key) {
  key.source = TermSource::Lookup;
  key.blurTaps = 0;
  key.atHalfTermDepth = true;
  return key;
}

void LightingPass::prepare(const ProgramKey& key) {
  if (key.source != TermSource::Upsample) {
    program(key);
    return;
  }
  program(nearHalfTermDepth(key));
  program(beyondHalfTermDepth(key));
}

const gl::Program& LightingPass::program(const ProgramKey& key) {
  auto it = programs_.find(key);
  if (it != programs_.end()) return it->second;
  std::vector<std::string> files{"lighting.frag", "sky_radiance.frag", "display_gamma.frag", "gbuffer_read.frag"};
  std::string defines = std::string(key.haze ? "#define HAZE\n" : "") + (key.record ? "#define RECORD_SHOWN\n" : "") +
                        (key.atHalfTermDepth ? "#define AT_HALF_TERM_DEPTH\n" : "") +
                        (key.atHalfTermDepth && key.source == TermSource::Lookup ? "#define WITH_SKY\n" : "");
  switch (key.source) {
    case TermSource::Lookup:
      files.push_back("shadow_lookup.frag");
      defines += shadowLookupDefines(key.shape);
      break;
    case TermSource::VerticalBlur:
      files.push_back("blur_taps.frag");
      defines += "#define BLURRED_TERM\n" + blurTapsDefine(key.blurTaps);
      break;
    case TermSource::Upsample:
      files.push_back("term_upsample.frag");
      defines += "#define UPSAMPLED_TERM\n";
      break;
  }
  return programs_.emplace(key, loadFullScreenProgram(files, defines)).first->second;
}

void LightingPass::run(const GBuffer& gbuffer, const gl::Texture* term, const ProgramKey& key, const gl::Texture& shadowMap,
                       const FrameBlockBuffer& frameBlock, bool keepTerm) {
  frameBlock.bind();
  // Without the term's target the shader's second output goes nowhere.
  const GLenum buffers[2] = {GL_COLOR_ATTACHMENT0, keepTerm ? GLenum{GL_COLOR_ATTACHMENT1} : GLenum{GL_NONE}};
  glNamedFramebufferDrawBuffers(framebuffer_.id(), 2, buffers);
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_.id());
  glViewport(0, 0, width_, height_);
  glDisable(GL_CULL_FACE);
  // The full-screen triangle lies at depth 0, the reversed-Z clear value: it passes GL_LESS where
  // the geometry pass drew (depth > 0) and GL_EQUAL where it did not. Fragments that fail are not
  // shaded (early depth test: the shaders neither discard nor write depth).
  glEnable(GL_DEPTH_TEST);
  glDepthMask(GL_FALSE);
  glDepthFunc(GL_LESS);
  bindShadowLookupInputs(gbuffer, shadowMap);
  if (key.source != TermSource::Lookup) glBindTextureUnit(4, term->id());
  if (key.source == TermSource::Upsample) {
    // Nearer than the half-resolution term's depth (FrameBlock::halfTerm), its upsample; beyond,
    // the lookup at every pixel, and the sky, which the depth test passes too.
    triangle_.draw(program(nearHalfTermDepth(key)));
    glDepthFunc(GL_GEQUAL);
    triangle_.draw(program(beyondHalfTermDepth(key)));
  } else {
    triangle_.draw(program(key));
    glDepthFunc(GL_EQUAL);
    triangle_.draw(sky_);
  }
  for (GLuint unit = 0; unit < 7; ++unit) glBindTextureUnit(unit, 0);
  glDepthFunc(GL_GREATER);  // the frame's reversed-Z state
  glDepthMask(GL_TRUE);
  glEnable(GL_CULL_FACE);
}

}  // namespace forest::render
