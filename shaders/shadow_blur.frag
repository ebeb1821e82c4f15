#version 450 core
// The horizontal pass of the eye-space blur (blur_taps.frag); lighting does the vertical one.
layout(binding = 0) uniform sampler2D uShadowTerm;
out vec2 blurred;

vec2 blurTaps(sampler2D term, ivec2 pixel, ivec2 direction);

void main() { blurred = blurTaps(uShadowTerm, ivec2(gl_FragCoord.xy), ivec2(1, 0)); }
