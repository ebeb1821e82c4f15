#include "blur_pass.hpp"

#include <algorithm>
#include <cmath>

namespace forest::render {

int blurTapsBound(double radius, int scale) {
  // As blur_taps.frag: σ = r/2 at full radius, less the upsample's tent, in texels; cut at 3σ and
  // at R/s. The 1e-4 keeps the bound at or above the shader's float result.
  const double sigmaImage = 0.5 * radius, s = scale;
  const double sigma = std::max(std::sqrt(std::max(sigmaImage * sigmaImage - (s * s - 1.0) / 6.0, 0.0)) / s, 0.25);
  return std::min({kMaxBlurTaps, static_cast<int>(std::ceil(radius / s)), static_cast<int>(3.0 * sigma + 1e-4)});
}

std::string blurTapsDefine(int taps) { return "#define BLUR_TAPS " + std::to_string(taps) + "\n"; }

const gl::Program& BlurPass::program(int taps, bool vertical, bool halfResolution) {
  const std::tuple key{taps, vertical, halfResolution};
  auto it = programs_.find(key);
  if (it == programs_.end())
    it = programs_.emplace(key, loadFullScreenProgram({"shadow_blur.frag", "blur_taps.frag"},
                                                      blurTapsDefine(taps) + (vertical ? "#define BLUR_VERTICAL\n" : "") +
                                                          (halfResolution ? "#define AT_HALF_TERM_REACH\n" : "")))
             .first;
  return it->second;
}

const gl::Texture& BlurPass::run(const gl::Texture& term, int scale, int taps, const gl::Texture* blockDepth,
                                  const FrameBlockBuffer& frameBlock) {
  const bool halfResolution = scale > 1;
  std::optional<Images>& images = images_[halfResolution ? 1 : 0];
  if (!images) {
    images.emplace(Images{PassImage(term.width(), term.height(), "blur"), std::nullopt});
    if (halfResolution) {
      images->vertical.emplace(term.width(), term.height(), "blur", GL_R32UI);
      images->horizontal.attachDepth(*blockDepth);
      images->vertical->attachDepth(*blockDepth);
    }
  }
  frameBlock.bind();
  // At half resolution only the blocks lighting reads: nearer than FrameBlock::halfTerm's reach (the
  // triangle at its depth, tested against the term's block depths); the rest the sky's, which
  // blur_taps.frag and the upsample ignore (eye depth 0).
  if (halfResolution) {
    images->horizontal.clearToSky();
    images->vertical->clearToSky();
    glEnable(GL_DEPTH_TEST);
    glDepthMask(GL_FALSE);
    glDepthFunc(GL_LESS);
  }
  images->horizontal.bindForDrawing();
  glBindTextureUnit(0, term.id());
  triangle_.draw(program(taps, false, halfResolution));
  if (!halfResolution) return images->horizontal.texture;
  images->vertical->bindForDrawing();
  glBindTextureUnit(0, images->horizontal.texture.id());
  triangle_.draw(program(taps, true, true));
  glDepthFunc(GL_GREATER);  // the frame's reversed-Z state
  glDepthMask(GL_TRUE);
  return images->vertical->texture;
}

}  // namespace forest::render
