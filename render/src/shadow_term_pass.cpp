#include "shadow_term_pass.hpp"

namespace forest::render {

using glm::dvec3;

ShadowTermPass::ShadowTermPass(int width, int height)
    : width_(width), height_(height), term_(GL_RG16F, width, height),
      program_(gl::loadProgram({"fullscreen.vert", "shadow_term.frag"})) {
  framebuffer_.attach(GL_COLOR_ATTACHMENT0, term_);
  framebuffer_.checkComplete("shadow term");
  glTextureParameteri(term_.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(term_.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
}

void ShadowTermPass::run(const GBuffer& gbuffer, const gl::Texture& shadowMap, const shadows::ShadowSetup& setup,
                         const glm::dmat4& eyeRelativeToShadow, const Camera& camera, const glm::mat3& rays,
                         const FrameSettings& settings, const dvec3& l, bool sunUp) {
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_.id());
  glViewport(0, 0, width_, height_);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  program_.set("uDepth", 0);
  program_.set("uGeometricNormal", 1);
  program_.set("uShadowMap", 3);
  program_.set("uRays", rays);
  glm::dmat4 lookup = eyeRelativeToShadow;
  if (settings.lookupShiftTexels != glm::dvec2(0.0)) {
    glm::dmat4 shift(1.0);  // clip x, y += 2·shift/size · w
    shift[3][0] = 2.0 * settings.lookupShiftTexels.x / settings.shadowMapSize;
    shift[3][1] = 2.0 * settings.lookupShiftTexels.y / settings.shadowMapSize;
    lookup = shift * lookup;
  }
  program_.set("uEyeRelativeToShadow", glm::mat4(lookup));
  program_.set("uLinearDepth", setup.linearDepth ? 1 : 0);
  program_.set("uEyeRelativeLightDepth", setup.eyeRelativeToLightDepthF);
  program_.set("uToSun", glm::vec3(-l));
  program_.set("uSunUp", sunUp ? 1 : 0);
  program_.set("uPcfRadius", settings.pcfRadius);
  program_.set("uNear", static_cast<float>(camera.near));
  program_.set("uFar", static_cast<float>(camera.far));
  glBindTextureUnit(0, gbuffer.depth.id());
  glBindTextureUnit(1, gbuffer.geometricNormal.id());
  glBindTextureUnit(3, shadowMap.id());
  triangle_.draw(program_);
}

}  // namespace forest::render
