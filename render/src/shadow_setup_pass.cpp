#include "shadow_setup_pass.hpp"

#include <algorithm>

#include "forest/shadows/casters.hpp"
#include "forest/shadows/focus_body.hpp"

namespace forest::render {
namespace {

using glm::dvec3;

// World size of one shadow-map texel at p (the larger of two directions across the light).
double texelWorldSize(const glm::dmat4& worldToShadowClip, int mapSize, const dvec3& p, const dvec3& l) {
  const auto [u, v] = shadows::axesAcrossLight(l);
  auto map = [&](const dvec3& q) {
    const glm::dvec4 h = worldToShadowClip * glm::dvec4(q, 1.0);
    return glm::dvec2(h) / h.w * (0.5 * mapSize);  // texels
  };
  const double step = 1e-3 * std::max(1.0, glm::length(p));
  const double alongU = glm::length(map(p + step * u) - map(p)) / step, alongV = glm::length(map(p + step * v) - map(p)) / step;
  const double texelsPerMetre = std::min(alongU, alongV);
  return texelsPerMetre > 0.0 ? 1.0 / texelsPerMetre : 0.0;
}

// 2×2 PCF reads the texels around the lookup: a receiver needs the casters of a footprint
// kFilterTexels wide around it, so receiver boxes grow by that many texels (their largest size
// over the box's corners) before casters are selected.
constexpr double kFilterTexels = 1.5;

// z_f for n moves 20% of the way to the new value each frame (§9.2.5: the visible set's z_f jumps
// when objects appear).
constexpr double kFarDepthSmoothing = 0.2;

// Casters of the visible receivers (DESIGN §4, Bittner et al. 2011): only the part of a receiver
// inside the view (up to z_f) receives visible shadows, so each box is clipped to V first (a
// 125 m terrain tile at the edge of the view does not pull in the casters of its unseen part),
// then grown by the filter footprint.
std::vector<std::uint32_t> castersOfReceivers(const std::vector<Aabb>& receivers, const Camera& shadowCamera,
                                              const shadows::ShadowSetup& setup, int mapSize, const dvec3& l,
                                              const SceneObjects& objects) {
  const ConvexBody view = shadows::viewFrustumBody(shadowCamera);
  std::vector<Aabb> footprints;
  for (const Aabb& receiver : receivers) {
    ConvexBody part = ConvexBody::fromBox(receiver);
    part.clip(view);
    if (!part.empty()) footprints.push_back(part.bounds());
  }
  for (Aabb& box : footprints) {
    double texel = 0.0;
    for (int c = 0; c < 8; ++c) texel = std::max(texel, texelWorldSize(setup.worldToShadowClip, mapSize, box.corner(c), l));
    box.min -= dvec3(kFilterTexels * texel);
    box.max += dvec3(kFilterTexels * texel);
  }
  const shadows::CasterSelector selector(l, footprints);
  return selector.select(objects.boxes());
}

}  // namespace

void ShadowSetupPass::run(const Camera& camera, const culling::CullingResult& visible, const FrameSettings& settings,
                          const dvec3& l, bool sunBelowHorizon, const SceneObjects& objects, const Aabb& sceneBounds,
                          ShadowPlan& plan, FrameStats& stats) {
  smoothedFarDepth_ = smoothedFarDepth_ < 0.0 ? visible.farDepth
                                               : smoothedFarDepth_ + kFarDepthSmoothing * (visible.farDepth - smoothedFarDepth_);
  stats.smoothedFarDepth = smoothedFarDepth_;
  std::vector<Aabb> receivers;
  Aabb receiverBounds;
  for (std::uint32_t o : visible.visibleObjects) {
    receivers.push_back(objects.boxes()[o]);
    receiverBounds.extend(objects.boxes()[o]);
  }
  plan.shadowed = !sunBelowHorizon && !receivers.empty() && sceneBounds.valid();
  plan.casters.clear();
  if (!plan.shadowed) return;
  shadows::ShadowInput input;
  input.camera = camera;
  const bool onReceivers = settings.focus == FocusBound::Receivers;
  if (onReceivers) input.camera.far = std::max(visible.farDepth, camera.near * 1.001);
  plan.camera = input.camera;
  input.sunDirection = l;
  input.scene = sceneBounds;
  if (onReceivers) input.receivers = receiverBounds;
  if (onReceivers && smoothedFarDepth_ > camera.near && smoothedFarDepth_ < input.camera.far) input.nFar = smoothedFarDepth_;
  input.mapSize = settings.shadowMapSize;
  plan.setup = shadows::computeShadowSetup(input, settings.method);
  stats.shadow = plan.setup.diagnostics;
  switch (settings.casters) {
    case CasterSelection::Receivers:
      plan.casters = castersOfReceivers(receivers, input.camera, plan.setup, settings.shadowMapSize, l, objects);
      break;
    case CasterSelection::FrustumBody: {
      const ConvexBody body = shadows::computeFocusBody(camera, l, sceneBounds);
      for (std::uint32_t o = 0; o < objects.boxes().size(); ++o)
        if (shadows::mayIntersect(body, objects.boxes()[o])) plan.casters.push_back(o);
      break;
    }
    case CasterSelection::All:
      for (std::uint32_t o = 0; o < objects.boxes().size(); ++o) plan.casters.push_back(o);
      break;
  }
}

}  // namespace forest::render
