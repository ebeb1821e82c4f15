#version 450 core
// Pass 4 (with the blur on): the shadow term of every pixel into a texture the blur reads
// (shadow_lookup.frag).

// r: the shadow term; g: the pixel's eye depth in metres (0 for the sky), so that the blur reads
// one texture per tap.
out vec2 shadowTerm;

uvec4 surfaceAt(ivec2 pixel);  // gbuffer_read.frag
vec2 shadowTermOf(uvec4 surface);

void main() { shadowTerm = shadowTermOf(surfaceAt(ivec2(gl_FragCoord.xy))); }
