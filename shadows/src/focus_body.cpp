#include "forest/shadows/focus_body.hpp"

namespace forest::shadows {

ConvexBody viewFrustumBody(const Camera& camera) {
  return ConvexBody::fromInverseViewProjection(glm::inverse(camera.projection() * camera.view()));
}

ConvexBody computeFocusBody(const Camera& camera, const glm::dvec3& lightDirection, const Aabb& scene,
                            const std::optional<Aabb>& receivers) {
  ConvexBody body = viewFrustumBody(camera);
  body.clip(scene);                                 // V ∩ S
  if (receivers) body.clip(*receivers);             // V ∩ R: only what is visible receives
  body.extrude(-lightDirection, scene);             // + l: towards the light, up to S
  body.clip(scene);                                 // ∩ S
  return body;
}

}  // namespace forest::shadows
