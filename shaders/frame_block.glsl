// The frame's full-screen-pass values (render/src/frame_uniforms.hpp: FrameBlock, std140,
// binding 2): written once per frame (DESIGN §9), read by the shadow term, blur and lighting.
layout(std140, binding = 2) uniform FrameBlock {
  mat4 eyeRelativeToShadow[4];    // per slice: (p − eye) → shadow clip with z already in [0, 1]
  vec4 eyeRelativeLightDepth[4];  // per slice, tsm: (p − eye, 1) → z_L in [−1, 1]
  vec4 rays[3];                // columns of the matrix taking (x_ndc, y_ndc, −1) to the ray at eye depth 1
  vec4 toSunUp;                // xyz: unit vector toward the sun; w: 1 when the sun is above the horizon
  vec4 sunColorAmbient;        // rgb: sun colour; w: ambient share
  vec4 skyFog;                 // rgb: sky colour, linear (the scene's to the power 2.2); w: fog density per metre (0: none)
  vec4 blur;                   // x: radius (image pixels), y: reference depth (m), z: relative depth tolerance,
                               // w: image pixels per shadow term texel side (1, or 2 at half resolution)
  vec4 cascadeEnds;            // the eye depth (m) where slice 0, 1, 2, 3 ends (pixels beyond read the next)
  vec4 cascadeBlend;           // x: the blend band beyond a split, as a share of its distance (0: none)
  ivec4 modes;                 // x: PCF radius; y: tsm linear depth (1/0); z: slices (1 to 4) — x and z
                               // are also the lookup program's PCF_RADIUS and SHADOW_SLICES;
                               // w: the map holds the sun's shadows (1/0; 0: the term is 0 everywhere)
  uvec4 imageRecord;           // x: this frame's stamp (0: record nothing), y: tiles per side, z: tiles
                               // (IDs 1 to z), w: the first block's slot (lighting.frag's recordShown)
  vec4 imageTerrain;           // xy: the eye in terrain samples from the heightfield's origin (x, z);
                               // z: 1 / sample spacing; w: quads per tile side
  vec4 halfTerm;               // x: the window depth (reversed-Z) of the eye depth within which lighting
                               // upsamples the half-resolution term (beyond, it looks the term up); y: that
                               // of the depth up to which the blur computes it; z, w: a, b of the window
                               // depth a / z + b of eye depth z
} uFrame;
