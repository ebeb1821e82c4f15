#pragma once
// Debug views of the last frame (forest render --debug).
#include <array>
#include <vector>

#include "forest/core/image.hpp"
#include "forest/render/frame.hpp"

namespace forest::render {

// Top-down diagram (world x to the right, z downwards) of the last frame's shadow setup: the view
// frustum up to z_f (black), the focus body B (blue), the light frustum — the shadow map's
// [−1, 1]³ mapped back to the world — (red), the visible receivers (green), the selected casters
// (orange outlines), the camera and the way the light travels. With cascades, each slice's B and
// light frustum in the slice's colour (cascadesPicture's). RGB: a legend band of
// kTopDownLegendHeight pixels on top, then the size × size diagram in a frame; what reaches beyond
// the diagram (the light frustum often does) is clipped at its frame, never drawn over the legend.
inline constexpr int kTopDownLegendHeight = 112;
Image8 topDownDiagram(const Frame& frame, const glm::dvec3& sunDirection, int size = 1024);

// The last frame's image with each pixel tinted by the slice whose layer it reads (slices 0–3:
// blue, teal, purple, red; the sky untinted). `camera`: the frame's (its near and far convert the
// depth buffer).
Image8 cascadesPicture(const Frame& frame, const Camera& camera);

// The shadow map (light depth per texel, rows bottom first, as Frame::readShadowMap gives them) as
// a picture: depths of the drawn texels stretched over their own range, near the light dark and far
// bright; texels no caster reached (still at the clear value 1) pale blue; under the map a band
// with the scale (the depths at its ends) and the share of texels drawn. RGB, size wide.
inline constexpr int kShadowMapLegendHeight = 44;
Image8 shadowMapPicture(const std::vector<float>& depth, int size);

// The 8 world corners of the shadow map's [−1, 1]³ (x, y: map, z: depth; linear depth for tsm).
std::array<glm::dvec3, 8> lightFrustumCorners(const shadows::ShadowSetup& setup);

}  // namespace forest::render
