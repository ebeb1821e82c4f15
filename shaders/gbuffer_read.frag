#version 450 core
// Readers of the geometry pass's surface target (gbuffer.frag has its layout), linked into the
// full-screen passes that read it: the shadow lookup's callers and lighting. One texel fetch per
// pixel gives all of it.
layout(binding = 5) uniform usampler2D uSurface;

uvec4 surfaceAt(ivec2 pixel) { return texelFetch(uSurface, pixel, 0); }
ivec2 lastPixel() { return textureSize(uSurface, 0) - 1; }
// The eye depths' bits of the 2 × 2 pixels from `corner`, in textureGather's order: (0, 1),
// (1, 1), (1, 0), (0, 0) (at the image's edge, clamped).
uvec4 surfaceGatherAt(ivec2 corner) { return textureGather(uSurface, vec2(corner + 1) / vec2(textureSize(uSurface, 0)), 0); }
float eyeDepthOf(uvec4 surface) { return uintBitsToFloat(surface.x); }  // 0: the sky
vec3 albedoOf(uvec4 surface) { return unpackUnorm4x8(surface.y).rgb; }
bool facesSunOf(uvec4 surface) { return (surface.y >> 24) >= 128u; }
bool onTerrainOf(uvec4 surface) { return (surface.y & (1u << 30)) != 0u; }
// Whether the half-resolution term keeps the surface apart from the sun-facing side of its
// terminator (its depth stored negated: shadow_term.frag, term_upsample.frag): it faces away from
// the sun and is not the terrain's.
bool keptApartOf(uvec4 surface) { return !facesSunOf(surface) && !onTerrainOf(surface); }
vec3 shadingNormalOf(uvec4 surface) {
  return normalize(vec3((uvec3(surface.z) >> uvec3(0, 10, 20)) & 1023u) * (2.0 / 1023.0) - 1.0);
}
