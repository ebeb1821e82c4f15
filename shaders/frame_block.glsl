// The frame's full-screen-pass values (render/src/frame_uniforms.hpp: FrameBlock, std140,
// binding 2): written once per frame (DESIGN §9), read by the shadow term, blur and lighting.
layout(std140, binding = 2) uniform FrameBlock {
  mat4 eyeRelativeToShadow;    // (p − eye) → shadow clip with z already in [0, 1]
  vec4 eyeRelativeLightDepth;  // tsm: (p − eye, 1) → z_L in [−1, 1]
  vec4 rays[3];                // columns of the matrix taking (x_ndc, y_ndc, −1) to the ray at eye depth 1
  vec4 toSunUp;                // xyz: unit vector toward the sun; w: 1 when the sun is above the horizon
  vec4 sunColorAmbient;        // rgb: sun colour; w: ambient share
  vec4 skyFog;                 // rgb: sky colour; w: fog density per metre (0: none)
  vec4 nearFar;                // x: near, y: far (metres)
  vec4 blur;                   // x: radius (pixels), y: reference depth (m), z: relative depth tolerance
  ivec4 modes;                 // x: PCF radius; y: tsm linear depth (1/0); z: unused (0: lighting picks its program by the blur, lighting_pass.cpp);
                               // w: the map holds the sun's shadows (1/0; 0: the term is 0 everywhere)
} uFrame;
