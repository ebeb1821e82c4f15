#version 450 core
// The lighting pass's term from the half-resolution blurred term (shadow_term.frag, TERM_SCALE 2):
// a joint bilateral upsample (Kopf et al., "Joint Bilateral Upsampling", SIGGRAPH 2007) over the
// 2 × 2 term texels whose centres surround the pixel — their bilinear weights, times 1 where a
// texel's depth is within the blur's relative tolerance (blur.z) of the pixel's and 0 elsewhere, so
// that a shadow does not cross a silhouette. Where no texel is that close (a surface thinner than
// the blocks around it lost all four to nearer ones), the term of the texel nearest in depth. One
// gather reads the four texels' terms and depths (packed as halves by the blur, shadow_blur.frag).
// Texel j of the term stands for pixels 2j and 2j + 1 (each axis): pixel p's centre lies at
// (p + 0.5) / 2 in the term's texel units, between texels floor(q) and floor(q) + 1, q = (p + 0.5) / 2 − 0.5.

// `z`: the pixel's eye depth, negated where keptApartOf (gbuffer_read.frag), as the term's texels
// store theirs (shadow_term.frag), so that it takes texels of its own side of a terminator.
vec2 upsampledTerm(usampler2D term, ivec2 pixel, float z) {
  if (z == 0.0) return vec2(1.0, 0.0);  // the sky
  vec2 q = (vec2(pixel) + 0.5) * 0.5 - 0.5;
  vec2 base = floor(q), f = q - base;
  // The corner the four texels share; the gathers' order: (0, 1), (1, 1), (1, 0), (0, 0) from base.
  vec2 uv = (base + 1.0) / vec2(textureSize(term, 0));
  uvec4 halves = textureGather(term, uv, 0);
  vec2 t0 = unpackHalf2x16(halves.x), t1 = unpackHalf2x16(halves.y), t2 = unpackHalf2x16(halves.z), t3 = unpackHalf2x16(halves.w);
  vec4 terms = vec4(t0.x, t1.x, t2.x, t3.x), depths = vec4(t0.y, t1.y, t2.y, t3.y);
  vec4 bilinear = vec4((1.0 - f.x) * f.y, f.x * f.y, f.x * (1.0 - f.y), (1.0 - f.x) * (1.0 - f.y));
  vec4 distance = abs(depths - z);
  vec4 weights = bilinear * step(distance, vec4(uFrame.blur.z * abs(z)));
  float sum = dot(weights, vec4(1.0));
  // The texel nearest in depth (ties: the first of x, y, z, w).
  float nearest = terms.x, best = distance.x;
  if (distance.y < best) { nearest = terms.y; best = distance.y; }
  if (distance.z < best) { nearest = terms.z; best = distance.z; }
  if (distance.w < best) { nearest = terms.w; }
  return vec2(sum > 0.0 ? dot(weights, terms) / sum : nearest, abs(z));
}
