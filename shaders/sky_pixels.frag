#version 450 core
// The lighting pass's sky (lighting_pass.cpp): drawn behind a depth test that passes only where the
// geometry pass drew nothing (the cleared depth), so that neither program pays for the other's
// pixels — llvmpipe runs both sides of a branch, but skips a block whose pixels all fail the test.
in vec3 vRay;

vec3 skyRadiance(vec3 d, vec3 zenith, vec3 toSun, vec3 sunColor, bool sunUp);  // sky.frag
vec3 displayFromLinear(vec3 linear);                                            // display_gamma.frag

layout(location = 0) out vec4 fragColor;
layout(location = 1) out vec2 usedTerm;  // as lighting.frag's: the sky's term is (1, eye depth 0)

void main() {
  usedTerm = vec2(1.0, 0.0);
  vec3 sky = skyRadiance(normalize(vRay), uFrame.skyFog.rgb, uFrame.toSunUp.xyz, uFrame.sunColorAmbient.rgb, uFrame.toSunUp.w != 0.0);
  fragColor = vec4(displayFromLinear(sky), 1.0);
}
