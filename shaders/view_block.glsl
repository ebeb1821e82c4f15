// The pass's view (render/view_block.hpp: ViewBlock, std140, binding 0), read by every surface
// shader; written once per view and pass into a mapped ring (DESIGN §9), not set per draw.
layout(std140, binding = 0) uniform ViewBlock {
  mat4 viewProjectionRelative;  // (p − view origin) → clip, composed in double
  vec4 lightDepthRow;           // LightDepth output: (p − view origin, 1) → z_L in [−1, 1]
  vec4 toSunAmbient;            // xyz: unit vector toward the sun; w: ambient share
  vec4 sunColorSlopeBias;       // rgb: sun colour; w: LightDepth slope-scale bias (0: none)
  vec4 viewer;                  // x: 1 when the view is the sun's (rays along −toSun), 0 an eye at the origin; y: +1 when the depth test keeps the lesser depth, −1 the greater
} uView;
