#version 450 core
// A far tree's impostor (impostor.vert): the baked texel under the fragment, its surface point —
// the viewer's side (the eye), or the nearest face turned away (the sun: a backside shadow map,
// Scherzer 2006 §5.1) — and the outputs trees.frag writes. What it writes stays inside the volumes
// the exact tests assume hold the tree: the fragment's line must cross them (the eye's line the
// culler's query boxes, the sun's the crown slabs the caster tests take), and the depth written is
// never nearer than where the line enters them — so a hidden query box or a caster test's "nothing
// nearer here" still proves the impostor hidden (issue "Far trees as impostors": exactness).
in vec2 vTexel;
in vec3 vQuad;
flat in vec3 vToViewer;
flat in vec4 vBaseScale;
flat in vec2 vYaw;
flat in vec3 vTint;
flat in uint vObjectId;
flat in uint vSpecies;
flat in float vFade;

layout(binding = 9) uniform usampler2DArray uImpostorAtlas;

#if defined(OUTPUT_GBUFFER)
void writeGBufferSurface(vec3 albedo, vec3 shadingNormal, float eyeDepth, bool facesSun, bool terrain, uint objectId);
#elif defined(OUTPUT_ID)
out uint fragId;
#elif defined(OUTPUT_QUERY_STAMP)
void writeQueryStamp(uint slot);
#elif !defined(OUTPUT_LIGHT_DEPTH)
out vec4 fragColor;
#endif

vec3 rotateYaw(vec3 p, vec2 cs) { return vec3(cs.x * p.x + cs.y * p.z, p.y, -cs.y * p.x + cs.x * p.z); }

// Where the line a + s·d enters the box [lo, hi] (s ≥ sMin), or 1e30 where it misses it.
float boxEntry(vec3 lo, vec3 hi, vec3 a, vec3 d, float sMin) {
  vec3 inv = 1.0 / mix(d, vec3(1e-20), equal(d, vec3(0.0)));
  vec3 s0 = (lo - a) * inv, s1 = (hi - a) * inv;
  vec3 near = min(s0, s1), far = max(s0, s1);
  float enter = max(max(near.x, near.y), max(near.z, sMin)), leave = min(min(far.x, far.y), far.z);
  return enter <= leave ? enter : 1e30;
}

// The line's entry into the tree's query boxes (Forest::treeQueryBoxes without the sway's growth,
// so inside the culler's; 1 mm in for float32): each slab's cylinder box cut to the species' box
// under the yaw and scale.
float queryBoxesEntry(vec3 a, vec3 d) {
  float scale = vBaseScale.w;
  vec3 lo = uImpostor.boxMin[vSpecies].xyz, hi = uImpostor.boxMax[vSpecies].xyz;
  vec3 mid = vBaseScale.xyz + scale * rotateYaw(0.5 * (lo + hi), vYaw), e = 0.5 * scale * (hi - lo);
  vec3 extent = vec3(abs(vYaw.x) * e.x + abs(vYaw.y) * e.z, e.y, abs(vYaw.y) * e.x + abs(vYaw.x) * e.z);
  float entry = 1e30;
  for (int k = 0; k < 4; ++k) {
    vec4 slab = uImpostor.querySlabs[vSpecies * 4u + uint(k)];
    if (slab.x > slab.y) continue;
    vec3 r = vec3(scale * slab.z, 0.0, scale * slab.z);
    vec3 boxLo = max(vBaseScale.xyz + vec3(-r.x, scale * slab.x, -r.z), mid - extent) + 1e-3;
    vec3 boxHi = min(vBaseScale.xyz + vec3(r.x, scale * slab.y, r.z), mid + extent) - 1e-3;
    entry = min(entry, boxEntry(boxLo, boxHi, a, d, 0.0));
  }
  return entry;
}

// The line's entry into the tree's crown slabs (Forest::placedCasterSlabs without the sway's
// growth, 1 mm in).
float crownSlabsEntry(vec3 a, vec3 d) {
  float scale = vBaseScale.w, entry = 1e30;
  for (int k = 0; k < 8; ++k) {
    vec4 slab = uImpostor.casterSlabs[vSpecies * 8u + uint(k)];
    if (slab.x > slab.y) continue;
    vec2 span = crownSlabSpan(Crown(vBaseScale.xyz, vec2(0.0), scale * slab.xy, scale * slab.zw), -1e-3, a, d);
    if (span.x <= span.y) entry = min(entry, span.x);
  }
  return entry;
}

// Whether p (relative to the view's origin) lies inside one of the tree's crown slabs with their
// faces moved in by 1 cm — inside those crownSlabsEntry takes (1 mm in), with room for float32.
bool insideCrownSlabs(vec3 p) {
  const float kIn = 1e-2;
  float scale = vBaseScale.w;
  vec3 q = p - vBaseScale.xyz;
  float across = max(max(abs(q.x), abs(q.z)), (abs(q.x) + abs(q.z)) * 0.70710678);  // the octagon's support at q
  bool inside = false;
  for (int k = 0; k < 8; ++k) {
    vec4 slab = uImpostor.casterSlabs[vSpecies * 8u + uint(k)];
    vec2 h = scale * slab.xy, r = scale * slab.zw;
    float slope = h.y > h.x ? (r.y - r.x) / (h.y - h.x) : 0.0;
    float apothem = r.x + slope * (q.y - h.x) - kIn * (1.0 + abs(slope));
    inside = inside || (slab.x <= slab.y && q.y >= h.x + kIn && q.y <= h.y - kIn && across <= apothem);
  }
  return inside;
}

// The pass's depth of a point (relative to the view's origin): the window depth, or the linear
// light depth (TSM §4, light_depth.frag) — and the farther of two as the pass's depth test sees it.
float passDepth(vec3 p) {
#if defined(OUTPUT_LIGHT_DEPTH)
  return 0.5 * dot(uView.lightDepthRow, vec4(p, 1.0)) + 0.5;
#else
  vec4 h = uView.viewProjectionRelative * vec4(p, 1.0);
  return h.z / h.w;
#endif
}
float fartherDepth(float a, float b) { return uView.viewer.y > 0.0 ? max(a, b) : min(a, b); }
// The point of the line a + s·d at pass depth `depth` (NaN or ∞ where the line keeps one depth).
vec3 pointAtDepth(vec3 a, vec3 d, float depth) {
#if defined(OUTPUT_LIGHT_DEPTH)
  return a + (depth - passDepth(a)) / (0.5 * dot(uView.lightDepthRow.xyz, d)) * d;
#else
  vec4 h0 = uView.viewProjectionRelative * vec4(a, 1.0), hd = uView.viewProjectionRelative * vec4(d, 0.0);
  return a + (depth * h0.w - h0.z) / (hd.z - depth * hd.w) * d;
#endif
}

void main() {
  uvec4 texel = texelFetch(uImpostorAtlas, ivec3(ivec2(floor(vTexel)), int(vSpecies)), 0);
  if ((texel.y >> 24) == 0u) discard;                            // not covered
  if (vFade < 1.0 && crossFadeDither(gl_FragCoord.xy) >= vFade) discard;  // the mesh's pixel
  bool fromSun = uView.viewer.x > 0.5;
  float s = uintBitsToFloat(fromSun ? texel.w : texel.x);
  vec3 surface = vQuad - s * vBaseScale.w * vToViewer;
  // The fragment's line: from the eye (the view's origin) through it, or along the sun's rays.
  vec3 a = fromSun ? vQuad : vec3(0.0), d = fromSun ? -uView.toSunAmbient.xyz : vQuad;
  float surfaceDepth = passDepth(surface), depth = surfaceDepth;
  vec3 written = surface;
  // From the sun: where the fragment's line is inside the crown slabs at the baked point's depth, it
  // entered them nearer — that depth stands, and the line test (the pass's dearest part on llvmpipe,
  // which skips a branch no fragment of a block takes) is needed only near the slabs' faces.
  if (!(fromSun && insideCrownSlabs(pointAtDepth(a, d, surfaceDepth)))) {
    float entry = fromSun ? crownSlabsEntry(a, d) : queryBoxesEntry(a, d);
    if (entry >= 1e30) discard;
    vec3 entered = a + entry * d;
    depth = fartherDepth(surfaceDepth, passDepth(entered));
    written = depth == surfaceDepth ? surface : entered;
  }
#if defined(OUTPUT_QUERY_STAMP)
  writeQueryStamp(vObjectId);  // early fragment tests: the quad's depth, nearer than `depth`
#else
  gl_FragDepth = clamp(depth, 0.0, 1.0);
#if defined(OUTPUT_GBUFFER)
  vec3 n = vec3((texel.zzz >> uvec3(0u, 10u, 20u)) & 0x3ffu) / 1023.0 * 2.0 - 1.0;
  n = rotateYaw(n, vYaw);
  vec3 albedo = unpackUnorm4x8(texel.y).rgb * vTint;
  float eyeDepth = (uView.viewProjectionRelative * vec4(written, 1.0)).w;
  writeGBufferSurface(albedo, n, eyeDepth, dot(n, uView.toSunAmbient.xyz) > 0.0, false, vObjectId);
#elif defined(OUTPUT_ID)
  fragId = vObjectId;
#elif !defined(OUTPUT_LIGHT_DEPTH)
  vec3 n = rotateYaw(vec3((texel.zzz >> uvec3(0u, 10u, 20u)) & 0x3ffu) / 1023.0 * 2.0 - 1.0, vYaw);
  float ambient = uView.toSunAmbient.w;
  vec3 linear = unpackUnorm4x8(texel.y).rgb * vTint * (ambient + (1.0 - ambient) * max(dot(normalize(n), uView.toSunAmbient.xyz), 0.0) * uView.sunColorSlopeBias.rgb);
  fragColor = vec4(pow(linear, vec3(1.0 / 2.2)), 1.0);
#endif
#endif
}
