#version 450 core
// Shadow casters tested on the GPU against the receiver mask (render/src/gpu_caster_filter.hpp;
// Bittner et al. 2011 §4 with box casters): a tree instance of the draw stays when one of its
// height slabs — a box round the cylinder of the species' widest point in that slab, under the
// instance's scale and wind shear, so it holds the triangles the draw places — projected into the
// map and grown by the lookups' reach, covers a texel whose farthest receiver lies beyond the
// slab's nearest point; where the footprint is small, texel by texel with the slab's crown frustum
// (crown_slabs.hpp): where the light's line through the texel centre enters it. The instances that stay are copied, group by group, into the output the
// shadow pass draws with glDrawElementsIndirect; each group's command counts them.
layout(local_size_x = 64) in;

struct Instance {  // TreeRenderer::InstanceGpu
  vec4 baseScale;      // base − view origin; scale
  vec4 rotationShear;  // cos, sin of the yaw; the wind's shear (x, z)
  vec4 tint;
  uint objectId, pad0, pad1, pad2;
};
struct Command {  // glDrawElementsIndirect's
  uint count, instanceCount, firstIndex;
  int baseVertex;
  uint baseInstance;
};
const int kMaxGroups = 32, kSlabs = 8, kMaxSpecies = 4;  // kSlabs: vegetation::kCasterSlabs

layout(std430, binding = 0) readonly buffer Input { Instance instances[]; };
layout(std430, binding = 1) writeonly buffer Output { Instance selected[]; };
layout(std430, binding = 2) buffer Commands { Command commands[]; };
layout(std430, binding = 3) buffer Selection { uint selectedCount; uint selectedIds[]; };
layout(std430, binding = 4) readonly buffer MaskFlags { uint everywhere; uint receivers; };
layout(std430, binding = 6) readonly buffer Params {
  vec4 slabs[kMaxSpecies * kSlabs];  // species s, slab k: height range (x, y) in object space (x > y: empty), frustum radii (z at x, w at y)
  uvec4 groups[kMaxGroups];          // first instance (relative), count, species, command index
  uint groupCount, instanceBase, instanceCount, commandBase;
};
layout(binding = 5) uniform usampler2D uMask;  // mip levels: the pyramid
layout(binding = 8) uniform usampler2D uReads;  // per texel the farthest receiver whose lookup may read it
layout(binding = 6) uniform sampler2D uOccluders;  // the map's largest depths, 2 × 2 texels per texel of level 0
layout(std430, binding = 7) readonly buffer Contributors { uint contributedIn[]; };  // per tree: the frame it last counted

uniform mat4 uToClip;
uniform mat4 uFromClip;  // its inverse: the map's clip coordinates → p − view origin
uniform vec4 uLightDepthRow;
uniform int uLinearDepth;
uniform int uMapSize, uLevels;
uniform float uReach;           // texels a lookup may read from its point, per axis
uniform float uDepthTolerance;  // float32 placement of receivers and casters
uniform uint uSelectionCapacity;  // object IDs the selection holds
// 0: every instance; 1: those that counted in the last frame's map (drawn first, the occluders);
// 2: the others, kept only where they may show over what phase 1 drew (uOccluders).
uniform int uPhase;
uniform uint uTreeIdBase, uTreeCount, uLastFrame;

// A box (relative to the view origin) in the map: the texels its corners span and its nearest
// map depth; `behind`: a corner lies behind the light's projection (or is not finite).
struct Footprint {
  vec2 tMin, tMax;
  float nearest;
  bool behind;
};
Footprint footprintOf(vec3 lo, vec3 hi) {
  Footprint f = Footprint(vec2(1e30), vec2(-1e30), 1e30, false);
  for (int c = 0; c < 8; ++c) {
    vec3 p = vec3((c & 1) != 0 ? hi.x : lo.x, (c & 2) != 0 ? hi.y : lo.y, (c & 4) != 0 ? hi.z : lo.z);
    vec4 h = uToClip * vec4(p, 1.0);
    if (!(h.w > 0.0)) f.behind = true;
    vec2 t = (h.xy / h.w * 0.5 + 0.5) * float(uMapSize);
    f.tMin = min(f.tMin, t);
    f.tMax = max(f.tMax, t);
    f.nearest = min(f.nearest, uLinearDepth != 0 ? 0.5 * dot(uLightDepthRow, vec4(p, 1.0)) + 0.5 : h.z / h.w);
  }
  f.behind = f.behind || any(isnan(f.tMin)) || any(isnan(f.tMax)) || isnan(f.nearest);
  return f;
}

// The level of a pyramid whose texels each cover 2^(level + shift) map texels at which the texels
// [a, b] span at most four per axis.
int levelFor(ivec2 a, ivec2 b, int shift, int levels) {
  int level = 0;
  while (level + 1 < levels && ((b.x >> (level + shift)) - (a.x >> (level + shift)) > 3 ||
                                (b.y >> (level + shift)) - (a.y >> (level + shift)) > 3))
    ++level;
  return level;
}

// Whether the box may shadow a receiver of the mask: a texel a lookup could reach the box from
// (its footprint grown by the reach; outside the map, its border) holds a receiver at or beyond
// the box's nearest point.
bool mayShadow(Footprint f) {
  if (f.behind) return true;
  float top = float(uMapSize - 1);
  ivec2 a = ivec2(clamp(floor(f.tMin - uReach), 0.0, top)), b = ivec2(clamp(floor(f.tMax + uReach), 0.0, top));
  int level = levelFor(a, b, 0, uLevels);
  // Texel t lies in min(t >> level, levelTop) (receiver_mask_reduce.comp); the level's size as
  // glTextureStorage2D gives it (textureSize at a level above 0 read wrong on llvmpipe here).
  ivec2 levelTop = ivec2(max(uMapSize >> level, 1) - 1);
  a = min(a >> level, levelTop);
  b = min(b >> level, levelTop);
  for (int y = a.y; y <= b.y; ++y)
    for (int x = a.x; x <= b.x; ++x) {
      uint farthest = texelFetch(uMask, ivec2(x, y), level).r;
      if (farthest != 0u && f.nearest <= uintBitsToFloat(farthest) + uDepthTolerance) return true;
    }
  return false;
}

// Whether the box may come nearer the light than what the map already holds at a texel whose
// centre it may cover (a fragment is made only there; kCentreMargin of a texel for float32 and the
// rasteriser's sub-texel snapping): else its fragments all fail the depth test, and drawing it
// changes no texel. The occluders' pyramid: level 0 the map's depths.
const float kCentreMargin = 1.0 / 16.0;
bool mayShowOverDrawn(Footprint f) {
  if (f.behind) return true;
  vec2 first = ceil(f.tMin - 0.5 - kCentreMargin), last = floor(f.tMax - 0.5 + kCentreMargin);
  if (any(greaterThan(first, last))) return false;  // covers no texel centre: draws nothing
  float top = float(uMapSize - 1);
  ivec2 a = ivec2(clamp(first, 0.0, top)), b = ivec2(clamp(last, 0.0, top));
  int level = levelFor(a, b, 0, uLevels);  // the occluders' pyramid has the mask's levels
  ivec2 levelLast = ivec2(max(uMapSize >> level, 1) - 1);  // as in mayShadow
  a = min(a >> level, levelLast);
  b = min(b >> level, levelLast);
  for (int y = a.y; y <= b.y; ++y)
    for (int x = a.x; x <= b.x; ++x)
      if (f.nearest - uDepthTolerance < texelFetch(uOccluders, ivec2(x, y), level).r) return true;
  return false;
}

// The light's line through map texel x's centre, relative to the view origin: a + s·d, the map
// depth growing with s (from the inverse of the map's matrix, uFromClip).
void lightLine(ivec2 x, out vec3 a, out vec3 d) {
  vec2 ndc = (vec2(x) + 0.5) / float(uMapSize) * 2.0 - 1.0;
  vec4 h0 = uFromClip * vec4(ndc, 0.0, 1.0), h1 = uFromClip * vec4(ndc, 1.0, 1.0);
  a = h0.xyz / h0.w;
  d = h1.xyz / h1.w - a;
}

float mapDepthAt(vec3 p) {
  vec4 h = uToClip * vec4(p, 1.0);
  return uLinearDepth != 0 ? 0.5 * dot(uLightDepthRow, vec4(p, 1.0)) + 0.5 : h.z / h.w;
}

// The depth at which the light's line through map texel x meets the crown slab grown by `grow`
// first — the least map depth of any point of it on that line (the depth along the line is
// monotonic where w > 0) — or 2 where the line misses it (crown_slab.glsl: crownSlabSpan).
float entryDepth(Crown c, float grow, ivec2 x) {
  vec3 a, d;
  lightLine(x, a, d);
  vec2 span = crownSlabSpan(c, grow, a, d);
  if (!(span.x <= span.y)) return 2.0;
  return min(mapDepthAt(a + span.x * d), mapDepthAt(a + span.y * d));
}

// A footprint small enough is tested texel by texel: it may matter only where the light's line
// through a texel centre meets it (grown by kCentreMargin of a texel for float32 and the
// rasteriser's snapping) at a depth a receiver reading that texel lies beyond and — phase 2 — the
// map does not already hold nearer. Larger ones: the two tests above, each over the whole footprint.
const int kExactTexels = 32;
bool mayMatter(vec3 lo, vec3 hi, Crown crown) {
  Footprint f = footprintOf(lo, hi);
  if (f.behind) return true;
  vec2 first = ceil(f.tMin - 0.5 - kCentreMargin), last = floor(f.tMax - 0.5 + kCentreMargin);
  float top = float(uMapSize - 1);
  first = max(first, vec2(0.0));
  last = min(last, vec2(top));
  if (any(greaterThan(first, last))) return false;  // no texel centre of the map: draws nothing
  ivec2 a = ivec2(first), b = ivec2(last);
  if (b.x - a.x >= kExactTexels || b.y - a.y >= kExactTexels) return mayShadow(f) && (uPhase != 2 || mayShowOverDrawn(f));
  // The margin in the world: kCentreMargin texels at the largest world size per texel the box spans
  // (its extent over the texels its corners span, at least one), and a centimetre.
  vec2 texels = max(f.tMax - f.tMin, vec2(1.0));
  float grow = kCentreMargin * length(hi - lo) / min(texels.x, texels.y) + 0.01;
  for (int y = a.y; y <= b.y; ++y)
    for (int x = a.x; x <= b.x; ++x) {
      uint farthest = texelFetch(uReads, ivec2(x, y), 0).r;
      if (farthest == 0u) continue;
      // tsm's matrix places x, y but not the depth it stores: there, the box's nearest point.
      float entry = (uLinearDepth != 0 ? f.nearest : entryDepth(crown, grow * (1.0 + length(crown.shear)), ivec2(x, y))) - uDepthTolerance;
      if (entry > uintBitsToFloat(farthest)) continue;  // misses (2), or behind every receiver reading the texel
      if (uPhase != 2 || entry < texelFetch(uOccluders, ivec2(x, y), 0).r) return true;
    }
  return false;
}

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= instanceCount) return;
  int g = 0;
  while (g + 1 < int(groupCount) && i >= groups[g + 1].x) ++g;
  Instance instance = instances[instanceBase + i];
  if (uPhase != 0) {
    uint tree = instance.objectId - uTreeIdBase;
    bool counted = tree < uTreeCount && uLastFrame != 0u && contributedIn[tree] == uLastFrame;
    if (counted != (uPhase == 1)) return;
  }
  bool keep = everywhere != 0u;
  float scale = instance.baseScale.w;
  vec2 shear = instance.rotationShear.zw;
  for (int k = 0; k < kSlabs && !keep; ++k) {
    vec4 slab = slabs[groups[g].z * uint(kSlabs) + uint(k)];
    if (slab.x > slab.y) continue;
    float h0 = scale * slab.x, h1 = scale * slab.y, r = scale * max(slab.z, slab.w);
    // trees.vert: x, z += shear · y after the scale and the yaw (a cylinder keeps its radius under the yaw).
    vec2 offsetLow = min(shear * h0, shear * h1), offsetHigh = max(shear * h0, shear * h1);
    vec3 lo = instance.baseScale.xyz + vec3(offsetLow.x - r, h0, offsetLow.y - r);
    vec3 hi = instance.baseScale.xyz + vec3(offsetHigh.x + r, h1, offsetHigh.y + r);
    keep = mayMatter(lo, hi, Crown(instance.baseScale.xyz, shear, vec2(h0, h1), scale * slab.zw));
  }
  if (!keep) return;
  uint command = commandBase + groups[g].w;
  uint slot = atomicAdd(commands[command].instanceCount, 1u);
  selected[commands[command].baseInstance + slot] = instance;
  uint id = atomicAdd(selectedCount, 1u);
  if (id < uSelectionCapacity) selectedIds[id] = instance.objectId;
}
