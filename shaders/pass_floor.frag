#version 450 core
// The floors of the full-screen passes (render/src/pass_floors.hpp): what a pass costs that does
// nothing but its reads — FLOOR_READS 0: none, a constant colour; 1: the G-buffer's surface texel
// (gbuffer_read.frag), as lighting reads it; 2: that and a gather of the half-resolution term, as
// lighting with the upsample reads them; 3: the surface's eye depths of a 2 × 2 block by one
// gather and the nearest one's texel, as the half-resolution term pass reads them (run on a
// quarter of the pixels); 4: three neighbouring texels of an RG16F term on a quarter of the pixels,
// as each half of the blur reads them at half resolution (one tap each side); 5: (3) and one
// hardware 2 × 2 PCF lookup of the shadow map, as the half-resolution term pass reads them; 6: (1)
// and one such lookup, as lighting reads them where it looks the term up (beyond the half term's
// depth, or the blur off). The lookups' texels are the map's at the pixel's place in the image,
// compared with a depth from the surface: the reads, not the projection into the map. What is
// read reaches the output, so no read is optimised away.
layout(location = 0) out vec4 color;

uvec4 surfaceAt(ivec2 pixel);
uvec4 surfaceGatherAt(ivec2 corner);
ivec2 lastPixel();
layout(binding = 4) uniform usampler2D uPackedTerm;
layout(binding = 0) uniform sampler2D uTerm;
layout(binding = 3) uniform sampler2DArrayShadow uShadowMap;

// One hardware PCF lookup at `uv` of the map's first layer, compared with a depth in [0, 1).
float mapLookup(vec2 uv, uvec4 surface) { return texture(uShadowMap, vec4(uv, 0.0, fract(uintBitsToFloat(surface.x)))); }

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
#if FLOOR_READS == 0
  color = vec4(0.25, 0.5, 0.75, 1.0);
#elif FLOOR_READS == 1
  color = unpackUnorm4x8(surfaceAt(pixel).y);
#elif FLOOR_READS == 2
  uvec4 halves = textureGather(uPackedTerm, (vec2(pixel / 2) + 0.5) / vec2(textureSize(uPackedTerm, 0)), 0);
  color = unpackUnorm4x8(surfaceAt(pixel).y ^ halves.x ^ halves.y ^ halves.z ^ halves.w);
#elif FLOOR_READS == 3 || FLOOR_READS == 5
  uvec4 depths = surfaceGatherAt(2 * pixel);
  uvec4 surface = surfaceAt(2 * pixel + ivec2(depths.x & 1u, depths.y & 1u));
#if FLOOR_READS == 3
  color = unpackUnorm4x8(surface.y);
#else
  color = unpackUnorm4x8(surface.y) * mapLookup((vec2(2 * pixel) + 1.0) / vec2(lastPixel() + 1), surface);
#endif
#elif FLOOR_READS == 6
  uvec4 surface = surfaceAt(pixel);
  color = unpackUnorm4x8(surface.y) * mapLookup((vec2(pixel) + 0.5) / vec2(lastPixel() + 1), surface);
#else
  ivec2 last = textureSize(uTerm, 0) - 1;
  vec2 sum = texelFetch(uTerm, pixel, 0).rg + texelFetch(uTerm, clamp(pixel - ivec2(1, 0), ivec2(0), last), 0).rg +
             texelFetch(uTerm, clamp(pixel + ivec2(1, 0), ivec2(0), last), 0).rg;
  color = vec4(sum, 0.0, 1.0);
#endif
}
