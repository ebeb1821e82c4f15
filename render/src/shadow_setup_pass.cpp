#include "shadow_setup_pass.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "forest/core/frustum.hpp"
#include "forest/shadows/casters.hpp"
#include "forest/shadows/focus_body.hpp"

namespace forest::render {
namespace {

using glm::dvec2;
using glm::dvec3;

// What the shadow term's filter reads (shaders/shadow_lookup.frag): a hardware 2×2 PCF lookup at a
// point reads the texels whose centres lie less than one texel from it along each map axis, and
// (2r+1)² lookups one texel apart reach r + 1 texels along each axis.
double filterReachTexels(int pcfRadius) { return pcfRadius + 1.0; }
// Beyond the reach: the GPU's float32 lookup coordinates and the rasteriser's fixed-point
// texel-centre test (8 sub-texel bits) — half a texel covers both many times over.
constexpr double kFilterMarginTexels = 0.5;

// The map keeps this many texels free around B, so that a lookup at B's border reads texels the
// shadow pass drew (DESIGN §4): the reach and the margin, rounded up.
int mapBorderTexels(int pcfRadius) {
  return static_cast<int>(std::ceil(filterReachTexels(pcfRadius) + kFilterMarginTexels));
}

// The largest world distance, across the light, that a map offset of (±1, ±1) texels (the corner
// of the filter's square footprint) spans at p: the inverse of the Jacobian of world (u, v) →
// map texels, exact for the projective map.
double texelCornerWorldSize(const glm::dmat4& worldToShadowClip, int mapSize, const dvec3& p, const dvec3& u, const dvec3& v) {
  const glm::dvec4 h = worldToShadowClip * glm::dvec4(p, 1.0);
  auto column = [&](const dvec3& d) {
    const glm::dvec4 e = worldToShadowClip * glm::dvec4(d, 0.0);
    return (0.5 * mapSize) * (dvec2(e) * h.w - dvec2(h) * e.w) / (h.w * h.w);  // texels per metre
  };
  const glm::dmat2 jacobian(column(u), column(v));
  const double determinant = glm::determinant(jacobian);
  if (!(std::abs(determinant) > 0.0) || !std::isfinite(determinant)) return std::numeric_limits<double>::infinity();
  const glm::dmat2 inverse = glm::inverse(jacobian);
  return std::max(glm::length(inverse * dvec2(1.0, 1.0)), glm::length(inverse * dvec2(1.0, -1.0)));
}

// A receiver box grown so that its projection on the map covers every texel the filter reads for
// a point in it: by reach + margin texels, at the largest texel size over its corners (twice,
// since the grown box reaches where texels may be larger). A box grown by g along every world
// axis contains every point within g of it, so its footprint across the light grows by ≥ g.
Aabb grownByFilter(Aabb box, const shadows::ShadowSetup& setup, int mapSize, double reachTexels, const dvec3& l,
                   const Aabb& sceneBounds) {
  const auto [u, v] = shadows::axesAcrossLight(l);
  const Aabb original = box;
  double grow = 0.0;
  for (int pass = 0; pass < 2; ++pass) {
    double worldPerTexel = 0.0;
    for (int c = 0; c < 8; ++c)
      worldPerTexel = std::max(worldPerTexel, texelCornerWorldSize(setup.worldToShadowClip, mapSize, box.corner(c), u, v));
    grow = std::max(grow, std::min(reachTexels * worldPerTexel, sceneBounds.diagonal()));  // ∞: every caster
    box = Aabb{original.min - dvec3(grow), original.max + dvec3(grow)};
  }
  return box;
}

}  // namespace

// Casters of the visible receivers (DESIGN §4, Bittner et al. 2011): only the part of a receiver
// inside the view (up to z_f) receives visible shadows, so each box is clipped to V first (a
// 125 m terrain tile at the edge of the view does not pull in the casters of its unseen part),
// then grown by the filter's footprint.
void ShadowSetupPass::selectCastersOfReceivers(const Camera& shadowCamera, const shadows::ShadowSetup& setup,
                                               const FrameSettings& settings, const dvec3& l, const SceneObjects& objects,
                                               const Aabb& sceneBounds, std::vector<std::uint32_t>& casters) {
  const ConvexBody view = shadows::viewFrustumBody(shadowCamera);
  const Frustum viewPlanes(shadowCamera);
  const double reach = filterReachTexels(settings.pcfRadius) + kFilterMarginTexels;
  footprints_.clear();
  for (const Aabb& receiver : receivers_) {
    // Most receivers (trees) lie wholly inside V: clipping would return the box itself.
    if (viewPlanes.contains(receiver)) {
      footprints_.push_back(grownByFilter(receiver, setup, settings.shadowMapSize, reach, l, sceneBounds));
      continue;
    }
    ConvexBody part = ConvexBody::fromBox(receiver);
    part.clip(view);
    if (!part.empty()) footprints_.push_back(grownByFilter(part.bounds(), setup, settings.shadowMapSize, reach, l, sceneBounds));
  }
  selector_.rebuild(l, footprints_);
  selector_.select(objects.boxes(), casters);
}

void ShadowSetupPass::run(const Camera& camera, const culling::CullingResult& visible, const FrameSettings& settings,
                          const dvec3& l, bool sunBelowHorizon, const SceneObjects& objects, const Aabb& sceneBounds,
                          ShadowPlan& plan, FrameStats& stats) {
  std::vector<Aabb>& receivers = receivers_;
  receivers.clear();
  // Room for every object as receiver and caster (a frame then never grows these lists).
  receivers_.reserve(objects.boxes().size());
  footprints_.reserve(objects.boxes().size());
  plan.casters.reserve(objects.boxes().size());
  selector_.reserve(objects.boxes().size());
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
  input.sunDirection = l;
  input.scene = sceneBounds;
  if (onReceivers) input.receivers = receiverBounds;
  // n over time (§9.2.5, shadows::kNearDistanceSmoothing): from the last frame's n, both ways.
  if (settings.method == shadows::ShadowMethod::Lispsm && previousN_ > 0.0) input.previousN = previousN_;
  input.mapSize = settings.shadowMapSize;
  input.borderTexels = mapBorderTexels(settings.pcfRadius);
  if (settings.method == shadows::ShadowMethod::UniformStable && stableRadius_ > 0.0) input.previousStableRadius = stableRadius_;
  if (const std::optional<std::string> outside = shadows::outsideShadowDomain(input)) {
    // A view too shallow for float32 this far from the origin: no shadows this frame, and why.
    plan.shadowed = false;
    stats.shadow.fallback = *outside;
    return;
  }
  plan.camera = input.camera;
  plan.setup = shadows::computeShadowSetup(input, settings.method);
  stats.shadow = plan.setup.diagnostics;
  if (settings.method == shadows::ShadowMethod::UniformStable) stableRadius_ = plan.setup.diagnostics.stableRadius;
  previousN_ = settings.method == shadows::ShadowMethod::Lispsm && !plan.setup.empty ? plan.setup.diagnostics.n : 0.0;
  switch (settings.casters) {
    case CasterSelection::Receivers:
      selectCastersOfReceivers(input.camera, plan.setup, settings, l, objects, sceneBounds, plan.casters);
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
