#pragma once
// The frame block's values (uniform_blocks.hpp: what the full-screen passes — shadow term, blur,
// lighting — read), composed in double once per frame and written once into a mapped ring
// (DESIGN §9) instead of a dozen glProgramUniform calls per pass.
#include <glm/glm.hpp>

#include "forest/core/camera.hpp"
#include "forest/core/scene.hpp"
#include "forest/gl/objects.hpp"
#include "forest/render/frame.hpp"
#include "forest/render/uniform_blocks.hpp"
#include "frame_block_buffer.hpp"
#include "shadow_setup_pass.hpp"

namespace forest::render {


// The blur averages only samples whose eye depth is within this share of the centre's (no bleeding
// across silhouettes; a sloped surface's depth changes less than this over 16 pixels).
constexpr double kBlurDepthTolerance = 0.05;
// How far beyond the depth where lighting stops upsampling the half-resolution term its passes
// compute it: three steps (the upsample, the vertical tap, the horizontal tap) of the tolerance.
constexpr double kHalfTermReach = (1.0 + kBlurDepthTolerance) * (1.0 + kBlurDepthTolerance) * (1.0 + kBlurDepthTolerance);

// The frame's distance haze per metre: the settings' fog density, else the scene's haze. Lighting
// compiles the haze in only where it is above 0 (HAZE, shaders/lighting.frag).
inline double hazeDensityOf(const FrameSettings& settings, const Scene& scene) { return settings.fogDensity.value_or(scene.render.haze); }

// This frame's block: `termScale` the image's pixels per shadow term texel side (the blur's
// radius is in image pixels), `l` the unit light direction, `sunUp` whether the sun is above the
// horizon; the plan says whether the map holds its shadows (else the term is 0 everywhere).
FrameBlock frameBlock(const Camera& camera, const ShadowPlan& plan, const FrameSettings& settings, int termScale,
                      const Scene& scene, const glm::dvec3& l, bool sunUp);

}  // namespace forest::render
