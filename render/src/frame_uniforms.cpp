#include "frame_uniforms.hpp"

#include <algorithm>

#include "fullscreen_triangle.hpp"
#include "shadow_pass.hpp"

namespace forest::render {
namespace {

// Error injection (FrameSettings::lookupShiftTexels): clip x, y += 2·shift/size · w.
glm::dmat4 lookupShift(const FrameSettings& settings, int size) {
  glm::dmat4 shift(1.0);
  if (size <= 0) return shift;  // no layer yet: nothing to shift (and no division by 0 towards the GPU)
  shift[3][0] = 2.0 * settings.lookupShiftTexels.x / size;
  shift[3][1] = 2.0 * settings.lookupShiftTexels.y / size;
  return shift;
}

// A layer of `size` texels per side in an array texture of `side` (FrameSettings::farSliceScale)
// is the square at its origin: the lookup's texture coordinate 0.5 · ndc + 0.5 scaled by f =
// size / side, i.e. ndc' = f · ndc + (f − 1), in clip space x' = f · x + (f − 1) · w.
glm::dmat4 layerSquare(int size, int side) {
  const double f = side > 0 ? static_cast<double>(size) / side : 1.0;
  glm::dmat4 m(1.0);
  m[0][0] = m[1][1] = f;
  m[3][0] = m[3][1] = f - 1.0;
  return m;
}

}  // namespace

double halfTermSplitDepth(const FrameSettings& settings) { return 0.5 * settings.blurRadius * settings.blurReferenceDepth; }

FrameBlock frameBlock(const Camera& camera, const ShadowPlan& plan, const FrameSettings& settings, int termScale,
                      const Scene& scene, const glm::dvec3& l, bool sunUp) {
  FrameBlock b;
  for (int i = 0; i < plan.cascades; ++i) {
    const ShadowSlice& slice = plan.slices[static_cast<size_t>(i)];
    b.eyeRelativeToShadow[i] = glm::mat4(layerSquare(slice.mapSize, plan.layerSide()) * lookupShift(settings, slice.mapSize) *
                                         eyeRelativeToShadowClip(slice.setup, camera.position));
    b.eyeRelativeLightDepth[i] = slice.setup.eyeRelativeToLightDepthF;
    b.cascadeEnds[i] = static_cast<float>(slice.to);
  }
  b.cascadeBlend = glm::vec4(static_cast<float>(plan.blend), 0.0f, 0.0f, 0.0f);
  const glm::mat3 rays = pixelRays(camera);
  for (int c = 0; c < 3; ++c) b.rays[c] = glm::vec4(rays[c], 0.0f);
  b.toSunUp = glm::vec4(glm::vec3(-l), sunUp ? 1.0f : 0.0f);
  b.sunColorAmbient = glm::vec4(glm::vec3(scene.sun.color), static_cast<float>(scene.sun.ambient));
  b.skyFog = glm::vec4(glm::vec3(glm::pow(scene.render.sky_color, glm::dvec3(2.2))), static_cast<float>(hazeDensityOf(settings, scene)));
  b.blur = glm::vec4(static_cast<float>(settings.blurRadius), static_cast<float>(settings.blurReferenceDepth),
                     static_cast<float>(kBlurDepthTolerance), static_cast<float>(termScale));
  if (termScale > 1) {
    // The split (halfTermSplitDepth), where the blur's radius r(z) = R · z_ref / z falls to 2
    // pixels: nearer, the term is smooth over a 2 × 2 block and the half-resolution one serves;
    // beyond, a half-resolution term would lose the map's detail, and the lighting looks the term
    // up at every pixel (blur_taps.frag).
    // The texels lighting reads for a pixel nearer than that lie within the blur's depth tolerance
    // (5%) of it, and their blur taps within 5% of theirs, and those taps' taps likewise: the term
    // and blur passes need nothing beyond 1.05³ of it (kHalfTermReach) and skip those blocks.
    const double split = halfTermSplitDepth(settings), reach = kHalfTermReach * split;
    // Reversed-Z (core/camera.cpp): eye depth z → window depth n (f − z) / (z (f − n)) = a / z + b.
    const double a = camera.near * camera.far / (camera.far - camera.near), bOffset = -camera.near / (camera.far - camera.near);
    const auto windowDepth = [&](double z) {
      return static_cast<float>(std::clamp(a / std::clamp(z, camera.near, camera.far) + bOffset, 0.0, 1.0));
    };
    b.halfTerm = glm::vec4(windowDepth(split), windowDepth(reach), static_cast<float>(a), static_cast<float>(bOffset));
  }
  b.modes = glm::ivec4(settings.pcfRadius, plan.slices[0].setup.linearDepth ? 1 : 0, plan.cascades, plan.shadowed ? 1 : 0);
  return b;
}

}  // namespace forest::render
