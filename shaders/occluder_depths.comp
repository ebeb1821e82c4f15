#version 450 core
// The occluders' pyramid of a shadow map layer (render/src/gpu_caster_filter.hpp): level 0 the
// map's layer itself (FROM_MAP), each level above the largest depth of the 2 × 2 texels below it
// (the last column and row of 3 where the level below has an odd size, as
// receiver_mask_reduce.comp). A box whose nearest depth is at or
// beyond the largest depth over its footprint can lower no texel of the map.
layout(local_size_x = 8, local_size_y = 8) in;
#ifdef FROM_MAP
layout(binding = 7) uniform sampler2DArray uMap;  // read with its comparison off
uniform int uLayer;
#else
layout(r32f, binding = 0) readonly uniform image2D uFiner;
#endif
layout(r32f, binding = 1) writeonly uniform image2D uCoarser;

float finer(ivec2 p, ivec2 last) {
#ifdef FROM_MAP
  return texelFetch(uMap, ivec3(min(p, last), uLayer), 0).r;
#else
  return imageLoad(uFiner, min(p, last)).r;
#endif
}

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy), coarse = imageSize(uCoarser);
  if (p.x >= coarse.x || p.y >= coarse.y) return;
#ifdef FROM_MAP
  ivec2 last = textureSize(uMap, 0).xy - 1;
#else
  ivec2 last = imageSize(uFiner) - 1;
#endif
#ifdef FROM_MAP
  imageStore(uCoarser, p, vec4(finer(p, last)));
  return;
#endif
  ivec2 q = 2 * p, end = min(q + 1 + ivec2(equal(p, coarse - 1)), last);
  float m = 0.0;
  for (int y = q.y; y <= end.y; ++y)
    for (int x = q.x; x <= end.x; ++x) m = max(m, finer(ivec2(x, y), last));
  imageStore(uCoarser, p, vec4(m));
}
