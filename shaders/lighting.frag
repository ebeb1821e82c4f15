#version 450 core
// Lighting (thesis §6.2): Phong — Lambert diffuse and a weak Blinn-Phong highlight from the sun,
// both times the shadow term — plus a weak global ambient; the sky colour where nothing was drawn.
// With the blur on, uShadowTerm is the horizontally blurred term and the vertical pass of the
// blur happens here (blur_taps.frag), saving a full-screen pass; with the blur off, the term is
// looked up here (shadow_lookup.frag) and no pass before writes it. The term used is written out.
in vec3 vRay;                 // eye depth z → camera-relative position z · vRay

layout(binding = 0) uniform sampler2D uAlbedo;
layout(binding = 1) uniform sampler2D uShadingNormal;
layout(binding = 4) uniform sampler2D uShadowTerm;  // r: term, g: eye depth (0: sky); read with the blur on
// The sun, sky, fog density (exponential fog toward the sky colour; 0: none) and whether to blur
// uShadowTerm vertically (it then holds the horizontal pass) come from the frame block.

layout(location = 0) out vec4 fragColor;
layout(location = 1) out vec2 usedTerm;  // the (blurred) term lit with: Frame::readBlurredShadowTerm

// Two programs (lighting_pass.cpp): BLURRED_TERM links blur_taps.frag, else shadow_lookup.frag. One
// program with both and a uniform branch costs the blur-on frame half again in this pass on
// llvmpipe, which runs both sides.
#ifdef BLURRED_TERM
vec2 blurTaps(sampler2D term, ivec2 pixel, ivec2 direction);
#else
vec2 shadowTermAt(ivec2 pixel, vec3 ray);
#endif

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  vec3 toSun = uFrame.toSunUp.xyz, sky = uFrame.skyFog.rgb;
  float ambient = uFrame.sunColorAmbient.w, fogDensity = uFrame.skyFog.w;
#ifdef BLURRED_TERM
  vec2 term = blurTaps(uShadowTerm, pixel, ivec2(0, 1));
#else
  vec2 term = shadowTermAt(pixel, vRay);
#endif
  usedTerm = term;
  if (term.g == 0.0) { fragColor = vec4(sky, 1.0); return; }
  vec3 albedo = texelFetch(uAlbedo, pixel, 0).rgb;
  vec3 n = normalize(texelFetch(uShadingNormal, pixel, 0).xyz);
  float shadow = term.r;
  vec3 linear = albedo * ambient;
  vec3 relative = term.g * vRay;
  if (uFrame.toSunUp.w != 0.0) {
    vec3 toEye = normalize(-relative);
    float diffuse = max(dot(n, toSun), 0.0);
    float c = max(dot(n, normalize(toSun + toEye)), 0.0);  // c^32 by squaring
    c *= c; c *= c; c *= c; c *= c; c *= c;
    float specular = c * step(0.0, dot(n, toSun));
    linear += (1.0 - ambient) * shadow * uFrame.sunColorAmbient.rgb * (albedo * diffuse + 0.04 * specular);
  }
  vec3 display = pow(linear, vec3(1.0 / 2.2));
  fragColor = vec4(fogDensity > 0.0 ? mix(sky, display, exp(-fogDensity * length(relative))) : display, 1.0);
}
