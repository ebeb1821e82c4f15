#pragma once
// Debug views of the last frame (forest render --debug).
#include <array>

#include "forest/core/image.hpp"
#include "forest/render/frame.hpp"

namespace forest::render {

// Top-down diagram (world x to the right, z downwards) of the last frame's shadow setup: the view
// frustum up to z_f (black), the focus body B (blue), the light frustum — the shadow map's
// [−1, 1]³ mapped back to the world — (red), the visible receivers (green), the selected casters
// (orange outlines), the camera and the way the light travels. RGB, size × size pixels.
Image8 topDownDiagram(const Frame& frame, const glm::dvec3& sunDirection, int size = 1024);

// The 8 world corners of the shadow map's [−1, 1]³ (x, y: map, z: depth; linear depth for tsm).
std::array<glm::dvec3, 8> lightFrustumCorners(const shadows::ShadowSetup& setup);

}  // namespace forest::render
