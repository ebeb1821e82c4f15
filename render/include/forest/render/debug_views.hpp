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
// blue, teal, purple, red; the sky untinted), over a legend band of kCascadesLegendHeight pixels:
// each slice's colour, its eye depths and its share of the image's pixels. `camera`: the frame's
// (its near and far convert the depth buffer); `stats`: the frame's (the slices' depths).
inline constexpr int kCascadesLegendHeight = 24;
Image8 cascadesPicture(const Frame& frame, const Camera& camera, const FrameStats& stats);

// A shadow term (1 lit, 0 shadow; rows bottom first, as Frame::readShadowTerm gives them) as a
// grey picture over a band of kCaptionHeight pixels with `caption` in it. RGB.
inline constexpr int kCaptionHeight = 22;
Image8 captionedTerm(const std::vector<float>& term, int width, int height, const std::string& caption);

// The shadow map (light depth per texel, rows bottom first, as Frame::readShadowMap gives them) as
// a picture: depths of the drawn texels stretched over their own range, near the light dark and far
// bright; texels no caster reached (still at the clear value 1) pale blue; under the map a band
// with the scale (the depths at its ends) and the share of the map the casters cover (not the
// frame record's texels_drawn: the texels the shadow pass drew into, covered or not). RGB, size wide.
inline constexpr int kShadowMapLegendHeight = 44;
Image8 shadowMapPicture(const std::vector<float>& depth, int size);

// The 8 world corners of the shadow map's [−1, 1]³ (x, y: map, z: depth; linear depth for tsm).
std::array<glm::dvec3, 8> lightFrustumCorners(const shadows::ShadowSetup& setup);

}  // namespace forest::render
