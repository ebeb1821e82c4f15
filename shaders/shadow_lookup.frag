#version 450 core
// The shadow term at a pixel from the G-buffer (DESIGN §4, thesis §9.3) — linked into the shadow
// term pass (shadow_term.frag, when the blur needs the term as a texture) and into lighting (the
// blur off: the term is looked up where it is used, and no full-screen pass writes it).
// The pixel's position from its eye depth, into the shadow map with the eye-relative light matrix
// (its ray in shadow clip space comes from fullscreen.vert), hardware 2×2 PCF (sampler2DShadow
// with linear filtering). Forced to 0 where the geometric normal faces away from the sun: backside
// rendering leaves noise on lee faces, and the eye-space blur must not spread it. The caller
// fetches the pixel's surface (gbuffer_read.frag) and hands it over, so that a pass reads each
// G-buffer texel once.
// The rest comes from the frame block (frame_block.glsl): the lookup matrices, tsm's linear light
// depth row, the sun, the slices' ends. The PCF radius (0: one hardware 2×2 lookup;
// r: (2r+1)² lookups a texel apart) and the slice count are compile-time constants, PCF_RADIUS and
// SHADOW_SLICES (render/src/shadow_term_pass.hpp: ShadowLookupPrograms).
layout(binding = 3) uniform sampler2DArrayShadow uShadowMap;  // a layer per slice; depth in [0, 1], near the light = 0

float eyeDepthOf(uvec4 surface);
bool facesSunOf(uvec4 surface);

// Per slice, the pixel's ray in shadow clip space and its tsm light depth (fullscreen.vert).
in vec4 vShadowRay[SHADOW_SLICES];
in float vLightDepthRay[SHADOW_SLICES];

// A pixel's rays in each slice: vShadowRay and vLightDepthRay at the pixel's centre, or, for the
// term at half resolution (shadow_term.frag), at the full-resolution pixel a term texel stands for.
struct SliceRays {
  vec4 shadow[SHADOW_SLICES];
  float lightDepth[SHADOW_SLICES];
};

// The rays `offset` pixels of this pass from the fragment's centre. They are linear in screen
// space, so their screen derivatives give them exactly anywhere; call in uniform control flow.
SliceRays sliceRaysAt(vec2 offset) {
  SliceRays r;
  for (int i = 0; i < SHADOW_SLICES; ++i) {
    r.shadow[i] = vShadowRay[i] + offset.x * dFdx(vShadowRay[i]) + offset.y * dFdy(vShadowRay[i]);
    r.lightDepth[i] = vLightDepthRay[i] + offset.x * dFdx(vLightDepthRay[i]) + offset.y * dFdy(vLightDepthRay[i]);
  }
  return r;
}

// The PCF term in one slice's layer of the point at eye depth z along `rays`: its shadow clip
// position M · (z · ray, 1) = z · rays.shadow + M[3].
float termInSlice(int slice, float z, SliceRays rays) {
  vec4 s = z * rays.shadow[slice] + uFrame.eyeRelativeToShadow[slice][3];
  vec3 ndc = s.xyz / s.w;
  // TSM: texture(s, vec3(xy_T / w_T, z_L / w_L)), w_L = 1 for the sun's orthographic L.
  if (uFrame.modes.y != 0) ndc.z = 0.5 * (z * rays.lightDepth[slice] + uFrame.eyeRelativeLightDepth[slice].w) + 0.5;
  vec2 uv = 0.5 * ndc.xy + 0.5;
  vec2 texel = 1.0 / vec2(textureSize(uShadowMap, 0).xy);
  const int radius = PCF_RADIUS;  // compile-time constants (ShadowLookupPrograms): the loops unroll
  float sum = 0.0;
  for (int y = -radius; y <= radius; ++y)
    for (int x = -radius; x <= radius; ++x) sum += texture(uShadowMap, vec4(uv + vec2(x, y) * texel, float(slice), ndc.z));
  return sum / float((2 * radius + 1) * (2 * radius + 1));
}

// r: the shadow term (1 lit, 0 shadowed); g: the pixel's eye depth in metres (0 for the sky).
// `surface`: the G-buffer texel of the pixel `rays` pass through.
// The slice is the first whose end lies beyond z (Zhang et al. 2006); in the blend band just past
// a split the nearer slice's term fades into the farther one's (that slice's B reaches over the
// band, render/src/shadow_setup_pass.cpp).
vec2 shadowTermAlong(uvec4 surface, SliceRays rays) {
  float z = eyeDepthOf(surface);
  if (z == 0.0) return vec2(1.0, 0.0);  // sky: the cleared surface
  if (uFrame.modes.w == 0 || !facesSunOf(surface)) return vec2(0.0, z);
  int slice = 0;
#if SHADOW_SLICES > 1
  for (int i = 0; i + 1 < SHADOW_SLICES; ++i) slice += z >= uFrame.cascadeEnds[i] ? 1 : 0;  // the ends increase
  float term = termInSlice(slice, z, rays);
  if (slice > 0) {
    float split = uFrame.cascadeEnds[slice - 1], band = uFrame.cascadeBlend.x * split;
    if (z < split + band) term = mix(termInSlice(slice - 1, z, rays), term, (z - split) / band);
  }
#else
  float term = termInSlice(0, z, rays);
#endif
  return vec2(term, z);
}

// The term of this fragment's own pixel.
vec2 shadowTermOf(uvec4 surface) {
  SliceRays rays;
  rays.shadow = vShadowRay;
  rays.lightDepth = vLightDepthRay;
  return shadowTermAlong(surface, rays);
}
