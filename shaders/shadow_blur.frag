#version 450 core
// One pass of the separable eye-space blur (blur_taps.frag): horizontal (BLUR_VERTICAL undefined)
// or vertical. At full resolution lighting does the vertical pass itself; at half resolution both
// run here, on a quarter of the pixels, and lighting upsamples the result.
// The vertical half writes the term and its depth as two halves of a uint (packHalf2x16), so that
// the upsample (term_upsample.frag) reads four texels with one gather.
layout(binding = 0) uniform sampler2D uShadowTerm;

vec2 blurTaps(sampler2D term, ivec2 pixel, ivec2 direction);

#ifdef BLUR_VERTICAL
out uint blurred;
void main() { blurred = packHalf2x16(blurTaps(uShadowTerm, ivec2(gl_FragCoord.xy), ivec2(0, 1))); }
#else
out vec2 blurred;
void main() { blurred = blurTaps(uShadowTerm, ivec2(gl_FragCoord.xy), ivec2(1, 0)); }
#endif
