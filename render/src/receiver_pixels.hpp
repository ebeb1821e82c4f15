#pragma once
// The visible receiver pixels of a frame for CasterSelection::ReceiverPixels: the G-buffer surface's
// eye depth and albedo (its alpha: whether the geometric normal faces the sun) read back (the CPU
// waits for the geometry pass), and for every pixel that faces the sun — the pixels whose shadow term is
// looked up (shaders/shadow_lookup.frag) — its ray's offsets and eye depth, which place it from the
// eye (shadows::ReceiverMask::addEyePoints). The rows are split into bands, one per hardware thread,
// each band's pixels gathered by a thread of its own: a software rasteriser's threads sit idle
// while the CPU works here, and the receiver mask fills band by band in the same way
// (ShadowSetupPass::fillReceiverMask). Storage is kept from frame to frame.
#include <glm/glm.hpp>

#include <functional>
#include <span>
#include <vector>

#include "forest/core/camera.hpp"
#include "forest/shadows/receiver_mask.hpp"
#include "geometry_pass.hpp"

namespace forest::render {

class ReceiverPixels {
 public:
  void read(const GBuffer& gbuffer, int width, int height, const Camera& camera);
  // The sun-facing pixels' centres, a list per band of rows: eye + z · (forward + x · right + y · up)
  // with rays().
  std::span<const std::vector<shadows::EyePoint>> bands() const { return bands_; }
  const shadows::EyeRays& rays() const { return rays_; }

 private:
  std::vector<glm::uvec2> surface_;  // the G-buffer surface's x and y (shaders/gbuffer.frag)
  std::vector<float> columns_;       // per column, the pixel centre's offset along right
  std::vector<std::vector<shadows::EyePoint>> bands_;
  shadows::EyeRays rays_{};
};

// Runs work(0) … work(count − 1), each but the first on a thread of its own, and returns when all
// are done.
void runInParallel(int count, const std::function<void(int)>& work);

// One band per hardware thread (at least 1, at most 8).
int receiverBands();

}  // namespace forest::render
