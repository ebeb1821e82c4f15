#pragma once
// What the shadow methods carry from one frame to the next, per slice (ShadowInput::carried):
// lispsm its n (smoothed over time, §9.2.5), uniform-stable its map radius (stableMapRadius); the
// others nothing. Each method decides what it carries (its file in shadows/src/method_*.cpp); a
// change of method on a slice, or a camera cut (reset), starts it afresh.
#include <array>
#include <optional>

#include "forest/shadows/cascades.hpp"
#include "forest/shadows/shadow_setup.hpp"

namespace forest::shadows {

class MethodHistory {
 public:
  // What the slice's last setup by `method` left for this frame's (0: nothing).
  double carried(ShadowMethod method, int slice) const;
  // Keeps what `method` carries from this frame's setup of the slice.
  void remember(ShadowMethod method, int slice, const ShadowSetup& setup);
  void reset();

 private:
  std::array<double, kMaxCascades> carried_{};
  std::array<std::optional<ShadowMethod>, kMaxCascades> by_{};
};

}  // namespace forest::shadows
