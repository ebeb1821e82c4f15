#include "shadow_term_pass.hpp"

namespace forest::render {

void bindShadowLookupInputs(const GBuffer& gbuffer, const gl::Texture& shadowMap) {
  glBindTextureUnit(5, gbuffer.surface.id());  // the bindings of shaders/gbuffer_read.frag and shadow_lookup.frag
  glBindTextureUnit(3, shadowMap.id());
}

std::string shadowLookupDefines(const ShadowLookupShape& shape) {
  return "#define PCF_RADIUS " + std::to_string(shape.pcfRadius) + "\n#define SHADOW_SLICES " + std::to_string(shape.slices) + "\n";
}

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
    : width_(width),
      height_(height),
      programs_{ShadowLookupPrograms({"shadow_term.frag"}, "#define TERM_SCALE 1\n"),
                ShadowLookupPrograms({"shadow_term.frag"}, "#define TERM_SCALE 2\n")} {}

void ShadowTermPass::run(const GBuffer& gbuffer, const gl::Texture& shadowMap, const ShadowLookupShape& shape, int scale,
                         const FrameBlockBuffer& frameBlock) {
  std::optional<PassImage>& image = images_[index(scale)];
  // A texel for every whole or partial block of scale × scale pixels.
  if (!image) {
    image.emplace((width_ + scale - 1) / scale, (height_ + scale - 1) / scale, "shadow term");
    if (scale > 1) {
      blockDepth_.emplace(GL_DEPTH_COMPONENT32F, image->texture.width(), image->texture.height());
      image->attachDepth(*blockDepth_);
    }
  }
  lastScale_ = scale;
  frameBlock.bind();
  image->bindForDrawing();
  glDisable(GL_CULL_FACE);
  bindShadowLookupInputs(gbuffer, shadowMap);
  if (scale == 1) {
    glDisable(GL_DEPTH_TEST);
    triangle_.draw(programs_[index(scale)].get(shape));
    return;
  }
  // At half resolution the term and, into the term's depth buffer, the block's nearest window
  // depth, against which the blur's passes skip the blocks lighting does not read.
  glEnable(GL_DEPTH_TEST);
  glDepthMask(GL_TRUE);
  glDepthFunc(GL_ALWAYS);
  triangle_.draw(programs_[index(scale)].get(shape));
  glDepthFunc(GL_GREATER);  // the frame's reversed-Z state
}

}  // namespace forest::render
