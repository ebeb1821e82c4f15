#version 450 core
// Which trees counted in a slice's map (render/src/gpu_caster_filter.hpp): a texel a receiver's
// lookup may read (a receiver within the reach, per axis, and at or beyond the texel's depth) that
// holds a tree's fragment marks that tree with the frame's number. The next frame draws those
// first, as the occluders the other trees are tested against; which trees they are decides only
// how many the frame draws, never the map (every tree that may lower a texel is drawn).
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 5) uniform usampler2D uMask;       // the receiver mask's pyramid
layout(binding = 7) uniform sampler2DArray uMap;    // read with its comparison off
layout(binding = 8) uniform usampler2DArray uIds;   // the object whose fragment each texel holds
layout(std430, binding = 7) buffer Contributors { uint contributedIn[]; };
uniform int uLayer, uMapSize, uLevels;
uniform float uReach, uDepthTolerance;
uniform uint uTreeIdBase, uTreeCount, uFrame;

void main() {
  ivec2 t = ivec2(gl_GlobalInvocationID.xy);
  if (t.x >= uMapSize || t.y >= uMapSize) return;
  uint tree = texelFetch(uIds, ivec3(t, uLayer), 0).r - uTreeIdBase;
  if (tree >= uTreeCount) return;  // terrain, a prop, or nothing drawn
  float depth = texelFetch(uMap, ivec3(t, uLayer), 0).r;
  int reach = int(ceil(uReach));
  ivec2 a = clamp(t - reach, ivec2(0), ivec2(uMapSize - 1)), b = clamp(t + reach, ivec2(0), ivec2(uMapSize - 1));
  int level = 0;
  while (level + 1 < uLevels && ((b.x >> level) - (a.x >> level) > 3 || (b.y >> level) - (a.y >> level) > 3)) ++level;
  ivec2 top = ivec2(max(uMapSize >> level, 1) - 1);  // texel t lies in min(t >> level, top) (receiver_mask_reduce.comp)
  a = min(a >> level, top);
  b = min(b >> level, top);
  for (int y = a.y; y <= b.y; ++y)
    for (int x = a.x; x <= b.x; ++x) {
      uint farthest = texelFetch(uMask, ivec2(x, y), level).r;
      if (farthest != 0u && depth <= uintBitsToFloat(farthest) + uDepthTolerance) {
        contributedIn[tree] = uFrame;
        return;
      }
    }
}
