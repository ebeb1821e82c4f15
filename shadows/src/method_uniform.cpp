// uniform: an orthographic map fitted to the focus body B in the light frame L (thesis §4.2; the
// LiSPSM warp with u = 0, §9.2.4). Carries nothing from frame to frame.
#include "light_space.hpp"
#include "shadow_methods.hpp"

namespace forest::shadows {

void setupUniform(const FocusedView& view, ShadowSetup& setup) {
  const FittedView fitted = fitView(view);
  setup.worldToShadowClip = fitUniform(fitted.lightFrame, fitted.fitVertices, clipBorder(view.in));
}

}  // namespace forest::shadows
