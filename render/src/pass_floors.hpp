#pragma once
// How far each full-screen pass is from what this renderer can do (issue "Half the full-screen
// cost"): passes that only read what the real ones read and write a colour, timed on the last
// frame's G-buffer (shaders/pass_floor.frag). On a software rasteriser a full-screen pass costs its
// pixels times its shader's work; these are the work-free part.
#include "forest/gl/objects.hpp"
#include "forest/gl/shader.hpp"
#include "forest/render/frame.hpp"
#include "fullscreen_triangle.hpp"
#include "geometry_pass.hpp"

namespace forest::render {

class PassFloors {
 public:
  PassFloors(int width, int height);
  // Each floor's median over `repeats` runs (glFinish before and after each), on `gbuffer` and the
  // frame's `shadowMap`.
  PassFloorTimes time(const GBuffer& gbuffer, const gl::Texture& shadowMap, int repeats);

 private:
  double timeOne(const gl::Program& program, const PassImage& target, int repeats) const;
  PassImage full_, half_;  // targets of the image's and of the half-resolution term's size
  // Read as the half-resolution term, packed (R32UI) and as the blur reads it (RG16F); what they
  // hold does not matter.
  gl::Texture packedTerm_, term_;
  gl::Program programs_[7];
  FullScreenTriangle triangle_;
};

}  // namespace forest::render
