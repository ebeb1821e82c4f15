#version 450 core
// Lighting (thesis §6.2): Phong — Lambert diffuse and a weak Blinn-Phong highlight from the sun,
// both times the shadow term — plus a weak hemispheric ambient (sky above, ground bounce below);
// distance haze. Drawn only where the geometry pass drew something (the depth test against its
// depth buffer, lighting_pass.cpp); sky.frag draws the rest.
// The shadow term, by program (lighting_pass.cpp): with the blur on at full resolution
// (BLURRED_TERM), uShadowTerm is the horizontally blurred term and the vertical pass of the blur
// happens here (blur_taps.frag), saving a full-screen pass; at half resolution (UPSAMPLED_TERM) the
// term blurred both ways is upsampled here (term_upsample.frag); with the blur off, the term is
// looked up here (shadow_lookup.frag) and no pass before writes it. The term used is written out.
in vec3 vRay;                 // eye depth z → camera-relative position z · vRay

// The pixel's surface: gbuffer_read.frag (the G-buffer's one texel).
uvec4 surfaceAt(ivec2 pixel);
float eyeDepthOf(uvec4 surface);
vec3 albedoOf(uvec4 surface);
vec3 shadingNormalOf(uvec4 surface);
// The sun, sky, haze density (exponential extinction per metre; 0: none) and the blur come from
// the frame block.

layout(location = 0) out vec4 fragColor;
layout(location = 1) out vec2 usedTerm;  // the (blurred) term lit with: Frame::readBlurredShadowTerm

// Programs (lighting_pass.cpp): BLURRED_TERM links blur_taps.frag, UPSAMPLED_TERM
// term_upsample.frag, else shadow_lookup.frag. One program with two and a uniform branch costs the blur-on frame half again in this pass on
// llvmpipe, which runs both sides. Likewise HAZE (the frame's haze density > 0) compiles the haze
// in: behind a uniform branch it cost the thesis walk 0.4 ms a frame without haze (800 × 600).
#if defined(UPSAMPLED_TERM)
bool keptApartOf(uvec4 surface);  // gbuffer_read.frag
layout(binding = 4) uniform usampler2D uPackedTerm;  // the half-resolution term (term_upsample.frag)
vec2 upsampledTerm(usampler2D term, ivec2 pixel, float z);
#elif defined(BLURRED_TERM)
layout(binding = 4) uniform sampler2D uShadowTerm;  // r: term, g: eye depth (0: sky)
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

// The sky's and the haze's colours (sky_radiance.frag).
vec3 hazeRadiance(vec3 d, vec3 zenith, vec3 toSun, vec3 sunColor, bool sunUp);
vec3 skyRadiance(vec3 d, vec3 zenith, vec3 toSun, vec3 sunColor, bool sunUp);

// The lit surface's radiance (linear).
vec3 surfaceRadiance(uvec4 surface, vec2 term, vec3 view, vec3 zenith, vec3 toSun, vec3 sunColor, bool sunUp, float ambient,
                     float hazeDensity) {
#ifdef WITH_SKY  // (the draw beyond the half-resolution term's depth, which the sky's pixels pass too)
  if (term.g == 0.0) return skyRadiance(view, zenith, toSun, sunColor, sunUp);
#endif
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
#if defined(UPSAMPLED_TERM)
  vec2 term = upsampledTerm(uPackedTerm, pixel, keptApartOf(surface) ? -eyeDepthOf(surface) : eyeDepthOf(surface));
#elif defined(BLURRED_TERM)
  vec2 term = blurTaps(uShadowTerm, pixel, ivec2(0, 1));
#else
  vec2 term = shadowTermOf(surface);
#endif
  usedTerm = term;
#ifdef RECORD_SHOWN  // (LightingPass: only where the frame does not take the record from its read-back)
  recordShown(surface);
#endif
  vec3 view = normalize(vRay);
  fragColor = vec4(displayFromLinear(surfaceRadiance(surface, term, view, zenith, toSun, sunColor, sunUp, ambient, hazeDensity)), 1.0);
}
