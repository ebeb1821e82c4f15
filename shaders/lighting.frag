#version 450 core
// Lighting (thesis §6.2): Phong — Lambert diffuse and a weak Blinn-Phong highlight from the sun,
// both times the shadow term — plus a weak hemispheric ambient (sky above, ground bounce below);
// distance haze; where nothing was drawn, a sky gradient with the sun's disc.
// With the blur on, uShadowTerm is the horizontally blurred term and the vertical pass of the
// blur happens here (blur_taps.frag), saving a full-screen pass; with the blur off, the term is
// looked up here (shadow_lookup.frag) and no pass before writes it. The term used is written out.
in vec3 vRay;                 // eye depth z → camera-relative position z · vRay

// The pixel's surface: gbuffer_read.frag (the G-buffer's one texel).
uvec4 surfaceAt(ivec2 pixel);
vec3 albedoOf(uvec4 surface);
vec3 shadingNormalOf(uvec4 surface);
layout(binding = 4) uniform sampler2D uShadowTerm;  // r: term, g: eye depth (0: sky); read with the blur on
// The sun, sky, haze density (exponential extinction per metre; 0: none) and whether to blur
// uShadowTerm vertically (it then holds the horizontal pass) come from the frame block.

layout(location = 0) out vec4 fragColor;
layout(location = 1) out vec2 usedTerm;  // the (blurred) term lit with: Frame::readBlurredShadowTerm

// Programs (lighting_pass.cpp): BLURRED_TERM links blur_taps.frag, else shadow_lookup.frag. One
// program with both and a uniform branch costs the blur-on frame half again in this pass on
// llvmpipe, which runs both sides. Likewise HAZE (the frame's haze density > 0) compiles the haze
// in: behind a uniform branch it cost the thesis walk 0.4 ms a frame without haze (800 × 600).
#ifdef BLURRED_TERM
vec2 blurTaps(sampler2D term, ivec2 pixel, ivec2 direction);
#else
vec2 shadowTermOf(uvec4 surface);
#endif

vec3 displayFromLinear(vec3 linear);  // γ 2.2 (display_gamma.frag)

#ifdef RECORD_SHOWN
// What shows in this image (render/src/image_visibility.hpp), for the next frame's culling: each
// pixel writes the frame's stamp into its object's slot (the G-buffer's ID) and, on a terrain
// tile, into the slot of its block of the 4 × 4 at levels 0–3 (terrain::Terrain::blockBoxes,
// row-major), found from the pixel's position. A pixel within rounding of a block's edge may mark
// the neighbour: the culler then asks one and draws the other untested, both exact.
layout(std430, binding = 7) writeonly buffer ImageRecord { uint shownStamp[]; };
float eyeDepthOf(uvec4 surface);  // gbuffer_read.frag
void recordShown(uvec4 surface) {
  uint stamp = uFrame.imageRecord.x, id = surface.w;
  if (stamp == 0u || id == 0u) return;
  shownStamp[id] = stamp;
  if (id > uFrame.imageRecord.z) return;
  uint tile = id - 1u, tilesPerSide = uFrame.imageRecord.y;
  int quads = int(uFrame.imageTerrain.w);
  vec2 samples = uFrame.imageTerrain.xy + eyeDepthOf(surface) * vRay.xz * uFrame.imageTerrain.z;
  ivec2 inTile = clamp(ivec2(floor(samples)) - ivec2(tile % tilesPerSide, tile / tilesPerSide) * quads, ivec2(0), ivec2(quads - 1));
  ivec2 block = inTile / (quads / 4);
  shownStamp[uFrame.imageRecord.w + tile * 16u + uint(block.y * 4 + block.x)] = stamp;
}
#endif

// x^8 by squaring: llvmpipe runs both sides of a branch, so the sky's terms are paid at every pixel,
// and pow is exp2(log2) there.
float pow8(float x) { x *= x; x *= x; return x * x; }

// The horizon's colour (linear): the zenith's, paled toward a hazy white.
vec3 horizonRadiance(vec3 zenith) { return mix(zenith, vec3(0.75, 0.8, 0.85), 0.55); }

// The sky (linear): the scene's sky colour at the zenith, paler toward the horizon (a gradient in
// elevation), a little darker below it, and, with the sun up, its disc (drawn 1.6° across so that
// it covers a few pixels; the real one is 0.53°) and a glow around it.
vec3 skyRadiance(vec3 d, vec3 zenith, vec3 toSun, vec3 sunColor, bool sunUp) {
  vec3 horizon = horizonRadiance(zenith);
  vec3 sky = d.y >= 0.0 ? mix(horizon, zenith, smoothstep(0.0, 0.6, d.y)) : horizon * (1.0 + 0.3 * d.y);
  if (!sunUp) return sky;
  float c = max(dot(d, toSun), 0.0);
  float disc = smoothstep(0.99985, 0.99990, c);  // cos 1.0° to cos 0.8°
  float c8 = pow8(c), c16 = c8 * c8, c128 = pow8(c16), c256 = c128 * c128;
  float glow = 0.6 * (c256 * c128 * c16) + 0.08 * c8;  // 0.6 c^400 + 0.08 c^8
  return sky + sunColor * (12.0 * disc + glow);
}

// The colour that distance haze fades toward along d: the horizon's, brighter toward the sun
// (light scattered forward).
vec3 hazeRadiance(vec3 d, vec3 zenith, vec3 toSun, vec3 sunColor, bool sunUp) {
  return horizonRadiance(zenith) + (sunUp ? 0.25 * sunColor * pow8(max(dot(d, toSun), 0.0)) : vec3(0.0));
}

// The pixel's radiance (linear): the sky where nothing was drawn (term.g, its eye depth, is 0),
// else the lit surface. One display encoding for both in main: llvmpipe runs both sides of the branch.
vec3 surfaceOrSky(uvec4 surface, vec2 term, vec3 view, vec3 zenith, vec3 toSun, vec3 sunColor, bool sunUp, float ambient,
                  float hazeDensity) {
  if (term.g == 0.0) return skyRadiance(view, zenith, toSun, sunColor, sunUp);
  vec3 albedo = albedoOf(surface);
  vec3 n = shadingNormalOf(surface);
  float shadow = term.r;
  // Hemispheric ambient: the sky's light from above (its colour at unit luminance), the ground's
  // bounce from below, blended by the normal's elevation.
  vec3 skyLight = mix(zenith, vec3(0.75, 0.8, 0.85), 0.5);
  skyLight /= max(dot(skyLight, vec3(0.2126, 0.7152, 0.0722)), 1e-4);
  const vec3 groundLight = vec3(0.42, 0.40, 0.30);
  vec3 linear = albedo * ambient * mix(groundLight, skyLight, 0.5 + 0.5 * n.y);
  vec3 relative = term.g * vRay;
  if (sunUp) {
    vec3 toEye = -view;
    float diffuse = max(dot(n, toSun), 0.0);
    float c = max(dot(n, normalize(toSun + toEye)), 0.0);  // c^32 by squaring
    c *= c; c *= c; c *= c; c *= c; c *= c;
    float specular = c * step(0.0, dot(n, toSun));
    linear += (1.0 - ambient) * shadow * sunColor * (albedo * diffuse + 0.04 * specular);
  }
#ifdef HAZE  // exponential extinction with in-scattered haze (linear light)
  linear = mix(hazeRadiance(view, zenith, toSun, sunColor, sunUp), linear, exp(-hazeDensity * length(relative)));
#endif
  return linear;
}

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  uvec4 surface = surfaceAt(pixel);
  vec3 toSun = uFrame.toSunUp.xyz, zenith = uFrame.skyFog.rgb;
  vec3 sunColor = uFrame.sunColorAmbient.rgb;
  bool sunUp = uFrame.toSunUp.w != 0.0;
  float ambient = uFrame.sunColorAmbient.w, hazeDensity = uFrame.skyFog.w;
#ifdef BLURRED_TERM
  vec2 term = blurTaps(uShadowTerm, pixel, ivec2(0, 1));
#else
  vec2 term = shadowTermOf(surface);
#endif
  usedTerm = term;
#ifdef RECORD_SHOWN  // (LightingPass: only where the frame does not take the record from its read-back)
  recordShown(surface);
#endif
  vec3 view = normalize(vRay);
  fragColor = vec4(displayFromLinear(surfaceOrSky(surface, term, view, zenith, toSun, sunColor, sunUp, ambient, hazeDensity)), 1.0);
}
