#version 450 core
// Pass 4 (with the blur on): the shadow term into a texture the blur reads (shadow_lookup.frag).
// TERM_SCALE 1: at every pixel. TERM_SCALE 2: at half resolution, one texel per 2 × 2 block of
// pixels, standing for the block's nearest surface — the lookup at that pixel's own position (its
// rays from their screen derivatives), so a thin twig in front of the ground keeps its term rather
// than the ground's; the block's other surfaces take theirs from the neighbouring texels in the
// lighting pass's depth-aware upsample (term_upsample.frag). Games compute the sun's shadow mask at
// reduced resolution for the same reason: after the blur the term is low-frequency.

// r: the shadow term; g: the eye depth in metres of the pixel it was looked up at (0 for the sky),
// so that the blur and the upsample read one texture per tap.
out vec2 shadowTerm;

uvec4 surfaceAt(ivec2 pixel);  // gbuffer_read.frag
ivec2 lastPixel();
uvec4 surfaceGatherAt(ivec2 corner);
bool keptApartOf(uvec4 surface);  // gbuffer_read.frag
float eyeDepthOf(uvec4 surface);
struct SliceRays {
  vec4 shadow[SHADOW_SLICES];
  float lightDepth[SHADOW_SLICES];
};
SliceRays sliceRaysAt(vec2 offset);
vec2 shadowTermOf(uvec4 surface);
vec2 shadowTermAlong(uvec4 surface, SliceRays rays);

#if TERM_SCALE == 1
void main() { shadowTerm = shadowTermOf(surfaceAt(ivec2(gl_FragCoord.xy))); }
#else
// The pixel of the block with the nearest surface (the sky, depth 0, only when the block is all
// sky; ties keep the first in the gather's order). One gather reads the block's four eye depths.
void main() {
  ivec2 corner = 2 * ivec2(gl_FragCoord.xy);
  // The gather's order from the corner: (0, 1), (1, 1), (1, 0), (0, 0); at an odd width or height
  // the edge's pixels again (clamped).
  vec4 depths = uintBitsToFloat(surfaceGatherAt(corner));
  vec4 candidates = mix(depths, vec4(3.0e38), equal(depths, vec4(0.0)));  // the sky last (still 3e38 if all sky)
  const ivec2 kInBlock[4] = ivec2[4](ivec2(0, 1), ivec2(1, 1), ivec2(1, 0), ivec2(0, 0));
  int chosen = 3;
  float best = candidates.w;
  for (int i = 0; i < 3; ++i)
    if (candidates[i] < best) {
      best = candidates[i];
      chosen = i;
    }
  ivec2 pixel = min(corner + kInBlock[chosen], lastPixel());
  // The fragment's centre is the block's centre: the chosen pixel's centre is ±1/4 of a texel off.
  uvec4 surface = surfaceAt(pixel);
  shadowTerm = shadowTermAlong(surface, sliceRaysAt(vec2(pixel - corner) * 0.5 - 0.25));
  // A surface facing away from the sun has the term 0 by fiat (shadow_lookup.frag), so its texels
  // must not stand for the sun-facing side of the same surface across the terminator: their depth
  // is stored negated, and the blur and the upsample, which take texels of equal depth only, keep
  // the two sides apart — except on the terrain, whose sun-facing side beside its terminator takes
  // the averted side's 0 into its blur as at full resolution (keeping them apart there lit pixels
  // the ray-traced truth shadows: docs/experiments.md).
  if (keptApartOf(surface)) shadowTerm.y = -shadowTerm.y;
  // The block's nearest window depth (reversed-Z, a/z + b) into the term's depth buffer, which the
  // blur's half-resolution passes test against (render/src/shadow_term_pass.hpp); the sky's 0.
  gl_FragDepth = best > 1.0e38 ? 0.0 : uFrame.halfTerm.z / best + uFrame.halfTerm.w;
}
#endif
