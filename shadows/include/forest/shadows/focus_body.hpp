#pragma once
// The focus body B (thesis §4.2, §9.2.2): the part of the scene that can cast a shadow visible
// in the view frustum V, for a directional light travelling along l:
//   B = ((V ∩ S) + l) ∩ S                                                         (eq. 4.2)
// where + is the extrusion of the clipped frustum towards the light up to S. With the visible
// receivers R known (occlusion culling), V ∩ S is replaced by V ∩ R: a tighter body.
#include <optional>

#include "forest/core/bounds.hpp"
#include "forest/core/camera.hpp"
#include "forest/core/convex_body.hpp"

namespace forest::shadows {

// V as a convex body, for the engine's zero-to-one clip convention.
ConvexBody viewFrustumBody(const Camera& camera);

// B for a directional light. `lightDirection` is the way light travels (need not be unit).
// `receivers`: bounds of the visible receivers (nullopt = use S). Returns an empty body when the
// frustum misses S (nothing visible to shadow).
ConvexBody computeFocusBody(const Camera& camera, const glm::dvec3& lightDirection, const Aabb& scene,
                            const std::optional<Aabb>& receivers = std::nullopt);

}  // namespace forest::shadows
