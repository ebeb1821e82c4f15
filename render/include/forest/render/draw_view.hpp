#pragma once
// How a pass sees the scene: a camera-relative view-projection composed in double (DESIGN §4),
// its origin, and the eye the level of detail belongs to — the eye pass draws its own LOD, the
// shadow pass draws the eye's LOD from the light (so casters match what the eye sees).
#include <glm/glm.hpp>

#include <string>

#include "forest/core/camera.hpp"
#include "forest/core/scene.hpp"
#include "forest/gl/shader.hpp"
#include "forest/render/uniform_blocks.hpp"

namespace forest::render {

struct DrawView {
  glm::dmat4 viewProjectionRelative{1.0};  // (p − origin) → clip
  glm::dvec3 origin{0.0};
  glm::dvec3 lodEye{0.0};                  // distances for tree LOD bands and terrain morphs
  double time = 0.0;                       // wind
  // SurfaceOutput::LightDepth (the TSM shadow pass): (p − origin, 1) → linear light depth in
  // [−1, 1], and the slope-scale bias the shader adds (polygon offset does not apply there).
  glm::dvec4 lightDepthRelative{0.0};
  double depthSlopeBias = 0.0;
  SunSettings sun;
  // The shadow pass's views: seen from the sun (impostors turn to it; the depth test keeps the
  // lesser depth), not from an eye at the origin with reversed-Z.
  bool fromSun = false;

  // The eye's own view.
  static DrawView fromCamera(const Camera& camera, double time, const SunSettings& sun);
};

// The view block the surface shaders read (uniform_blocks.hpp), composed in double and
// converted once (DESIGN §4). The wind's sway is per tree instance (TreeRenderer).
ViewBlock viewBlock(const DrawView& view);

// Framebuffer outputs every renderer offers: lit colour, object ID (GL_R32UI), the G-buffer of
// the geometry pass (albedo, shading normal, geometric normal, object ID; see gbuffer.frag), or
// depth only (the shadow pass: nothing but depth is attached).
// LightDepth: depth only, written as the linear light depth (TSM §4, light_depth.frag).
// QueryStamp: nothing written but the occlusion culler's frame stamp, into the result slot the
// object ID carries, by each fragment that passes the depth test (query_stamp.frag: a geometry query).
enum class SurfaceOutput { Lit, ObjectId, GBuffer, LightDepth, QueryStamp };

// A surface program for an output: defines OUTPUT_ID or OUTPUT_GBUFFER (and links gbuffer.frag);
// every stage gets the view block's declaration (view_block.glsl).
gl::Program loadSurfaceProgram(const std::string& vertex, const std::string& fragment, SurfaceOutput output,
                               const std::string& extraDefines = "");

}  // namespace forest::render
