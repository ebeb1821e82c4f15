#version 450 core
// Shadow casters tested on the GPU against the receiver mask (render/src/gpu_caster_filter.hpp;
// Bittner et al. 2011 §4 with box casters): a tree instance of the draw stays when one of its
// height slabs — a box round the cylinder of the species' widest point in that slab, under the
// instance's scale and wind shear, so it holds the triangles the draw places — projected into the
// map and grown by the lookups' reach, covers a texel whose farthest receiver lies beyond the
// slab's nearest point. The instances that stay are copied, group by group, into the output the
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
const int kMaxGroups = 16, kSlabs = 4, kMaxSpecies = 4;

layout(std430, binding = 0) readonly buffer Input { Instance instances[]; };
layout(std430, binding = 1) writeonly buffer Output { Instance selected[]; };
layout(std430, binding = 2) buffer Commands { Command commands[]; };
layout(std430, binding = 3) buffer Selection { uint selectedCount; uint selectedIds[]; };
layout(std430, binding = 4) readonly buffer MaskFlags { uint everywhere; uint receivers; };
layout(std430, binding = 6) readonly buffer Params {
  vec4 slabs[kMaxSpecies * kSlabs];  // species s, slab k: height range (x, y) in object space (x > y: empty), radius z
  uvec4 groups[kMaxGroups];          // first instance (relative), count, species, command index
  uint groupCount, instanceBase, instanceCount, commandBase;
};
layout(binding = 5) uniform usampler2D uMask;  // mip levels: the pyramid

uniform mat4 uToClip;
uniform vec4 uLightDepthRow;
uniform int uLinearDepth;
uniform int uMapSize, uLevels;
uniform float uReach;           // texels a lookup may read from its point, per axis
uniform float uDepthTolerance;  // float32 placement of receivers and casters
uniform uint uSelectionCapacity;  // object IDs the selection holds

// Whether the box [lo, hi] (relative to the view origin) may shadow a receiver of the mask.
bool mayShadow(vec3 lo, vec3 hi) {
  vec2 tMin = vec2(1e30), tMax = vec2(-1e30);
  float nearest = 1e30;
  for (int c = 0; c < 8; ++c) {
    vec3 p = vec3((c & 1) != 0 ? hi.x : lo.x, (c & 2) != 0 ? hi.y : lo.y, (c & 4) != 0 ? hi.z : lo.z);
    vec4 h = uToClip * vec4(p, 1.0);
    if (!(h.w > 0.0)) return true;  // reaches behind the light's projection
    vec2 t = (h.xy / h.w * 0.5 + 0.5) * float(uMapSize);
    tMin = min(tMin, t);
    tMax = max(tMax, t);
    nearest = min(nearest, uLinearDepth != 0 ? 0.5 * dot(uLightDepthRow, vec4(p, 1.0)) + 0.5 : h.z / h.w);
  }
  if (any(isnan(tMin)) || any(isnan(tMax)) || isnan(nearest)) return true;
  // The texels whose receivers a lookup could reach the box from; outside the map, its border.
  float top = float(uMapSize - 1);
  ivec2 a = ivec2(clamp(floor(tMin - uReach), 0.0, top)), b = ivec2(clamp(floor(tMax + uReach), 0.0, top));
  int level = 0;
  while (level + 1 < uLevels && ((b.x >> level) - (a.x >> level) > 3 || (b.y >> level) - (a.y >> level) > 3)) ++level;
  a >>= level;
  b >>= level;
  for (int y = a.y; y <= b.y; ++y)
    for (int x = a.x; x <= b.x; ++x) {
      uint farthest = texelFetch(uMask, ivec2(x, y), level).r;
      if (farthest != 0u && nearest <= uintBitsToFloat(farthest) + uDepthTolerance) return true;
    }
  return false;
}

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= instanceCount) return;
  int g = 0;
  while (g + 1 < int(groupCount) && i >= groups[g + 1].x) ++g;
  Instance instance = instances[instanceBase + i];
  bool keep = everywhere != 0u;
  float scale = instance.baseScale.w;
  vec2 shear = instance.rotationShear.zw;
  for (int k = 0; k < kSlabs && !keep; ++k) {
    vec4 slab = slabs[groups[g].z * uint(kSlabs) + uint(k)];
    if (slab.x > slab.y) continue;
    float h0 = scale * slab.x, h1 = scale * slab.y, r = scale * slab.z;
    // trees.vert: x, z += shear · y after the scale and the yaw (a cylinder keeps its radius under the yaw).
    vec2 offsetLow = min(shear * h0, shear * h1), offsetHigh = max(shear * h0, shear * h1);
    vec3 lo = instance.baseScale.xyz + vec3(offsetLow.x - r, h0, offsetLow.y - r);
    vec3 hi = instance.baseScale.xyz + vec3(offsetHigh.x + r, h1, offsetHigh.y + r);
    keep = mayShadow(lo, hi);
  }
  if (!keep) return;
  uint command = commandBase + groups[g].w;
  uint slot = atomicAdd(commands[command].instanceCount, 1u);
  selected[commands[command].baseInstance + slot] = instance;
  uint id = atomicAdd(selectedCount, 1u);
  if (id < uSelectionCapacity) selectedIds[id] = instance.objectId;
}
