#pragma once
// Pass 4 of the frame (thesis §9.4, DESIGN §4), run only when the blur is on: the shadow term, full
// screen from the G-buffer — hardware 2×2 PCF (sampler2DShadow), (2r+1)² of them for a wider
// filter, 0 where the geometric N·L ≤ 0 before any blur. Target: RG16F (the term; the blur's
// inputs). With the blur off the lighting pass looks the term up itself (shaders/shadow_lookup.frag):
// one full-screen pass fewer.
#include <glm/glm.hpp>

#include "forest/gl/objects.hpp"
#include "forest/gl/shader.hpp"
#include "forest/render/frame.hpp"
#include "fullscreen_triangle.hpp"
#include "geometry_pass.hpp"

namespace forest::render {

// Binds what shaders/shadow_lookup.frag reads: the G-buffer's depth and geometric normal, the map.
void bindShadowLookupInputs(const GBuffer& gbuffer, const gl::Texture& shadowMap);

class ShadowTermPass {
 public:
  ShadowTermPass(int width, int height);
  // Reads the lookup, the sun and the filter from the frame block (frame_uniforms.hpp), bound.
  void run(const GBuffer& gbuffer, const gl::Texture& shadowMap);
  const gl::Texture& term() const { return term_; }

 private:
  int width_, height_;
  gl::Texture term_;
  gl::Framebuffer framebuffer_;
  gl::Program program_;
  FullScreenTriangle triangle_;
};

}  // namespace forest::render
