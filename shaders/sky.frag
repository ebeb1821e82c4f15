#version 450 core
// The sky where the geometry pass drew nothing (thesis §6.2's lighting leaves it out: lighting_pass.cpp
// draws this only where the depth buffer holds the clear value, and lighting.frag only elsewhere, so
// that neither pays for the other's pixels — llvmpipe runs both sides of a branch). The term used
// there is 1, at eye depth 0, as the term passes write for the sky.
in vec3 vRay;
layout(location = 0) out vec4 fragColor;
layout(location = 1) out vec2 usedTerm;

vec3 skyRadiance(vec3 d, vec3 zenith, vec3 toSun, vec3 sunColor, bool sunUp);  // sky_radiance.frag
vec3 displayFromLinear(vec3 linear);  // display_gamma.frag

void main() {
  vec3 sky = skyRadiance(normalize(vRay), uFrame.skyFog.rgb, uFrame.toSunUp.xyz, uFrame.sunColorAmbient.rgb, uFrame.toSunUp.w != 0.0);
  fragColor = vec4(displayFromLinear(sky), 1.0);
  usedTerm = vec2(1.0, 0.0);
}
