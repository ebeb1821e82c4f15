#include "shadow_term_pass.hpp"

namespace forest::render {

void bindShadowLookupInputs(const GBuffer& gbuffer, const gl::Texture& shadowMap) {
  glBindTextureUnit(5, gbuffer.surface.id());  // the bindings of shaders/gbuffer_read.frag and shadow_lookup.frag
  glBindTextureUnit(3, shadowMap.id());
}

namespace {
// The lines that make `shape` compile-time constants of shaders/shadow_lookup.frag.
std::string shadowLookupDefines(const ShadowLookupShape& shape) {
  return "#define PCF_RADIUS " + std::to_string(shape.pcfRadius) + "\n#define SHADOW_SLICES " + std::to_string(shape.slices) + "\n";
}
}  // namespace

ShadowLookupPrograms::ShadowLookupPrograms(std::vector<std::string> fragments, std::string defines)
    : fragments_(std::move(fragments)), defines_(std::move(defines)) {
  fragments_.push_back("shadow_lookup.frag");
  fragments_.push_back("gbuffer_read.frag");
}

const gl::Program& ShadowLookupPrograms::get(const ShadowLookupShape& shape) {
  auto it = programs_.find(shape);
  if (it == programs_.end()) it = programs_.emplace(shape, loadFullScreenProgram(fragments_, defines_ + shadowLookupDefines(shape))).first;
  return it->second;
}

ShadowTermPass::ShadowTermPass(int width, int height)
    : width_(width), height_(height), term_(GL_RG16F, width, height), programs_({"shadow_term.frag"}) {
  framebuffer_.attach(GL_COLOR_ATTACHMENT0, term_);
  framebuffer_.checkComplete("shadow term");
  glTextureParameteri(term_.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(term_.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
}

void ShadowTermPass::run(const GBuffer& gbuffer, const gl::Texture& shadowMap, const ShadowLookupShape& shape,
                         const FrameBlockBuffer& frameBlock) {
  frameBlock.bind();
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_.id());
  glViewport(0, 0, width_, height_);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  bindShadowLookupInputs(gbuffer, shadowMap);
  triangle_.draw(programs_.get(shape));
}

}  // namespace forest::render
