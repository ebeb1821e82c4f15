#pragma once
// The nearest visible eye depth of a frame, for the cascades' split scheme (DESIGN §4; Lauritzen et
// al., "Sample Distribution Shadow Maps", 2011: the depth buffer bounds the visible range tighter
// than any box). A compute shader reduces the G-buffer's reversed-Z depth to its largest value
// (shaders/nearest_depth.comp). The result is read one frame later from a ring of two buffers, so
// nothing in a frame waits for the GPU (DESIGN §9); only the first frame after a reset reads its
// own at once. The splits only place the slices — every slice's B holds its whole depth range —
// so a value a frame old costs resolution, never correctness.
#include <array>
#include <optional>

#include "forest/core/camera.hpp"
#include "forest/gl/objects.hpp"
#include "forest/gl/shader.hpp"

namespace forest::render {

class NearestDepthPass {
 public:
  NearestDepthPass();
  // Starts the reduction of this frame's depth and returns the nearest eye depth (metres) of the
  // frame before (this frame's after a reset): none when nothing was drawn. `camera`: this frame's
  // (its near and far convert the depth).
  std::optional<double> run(const gl::Texture& depth, const Camera& camera);
  void reset() { havePrevious_ = false; }

 private:
  double read(int buffer, const Camera& camera) const;  // 0: nothing drawn

  gl::Program program_;
  std::array<gl::Buffer, 2> buffers_;
  int next_ = 0;
  bool havePrevious_ = false;
};

}  // namespace forest::render
