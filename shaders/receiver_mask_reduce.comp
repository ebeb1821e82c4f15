#version 450 core
// One level of the receiver mask's pyramid (render/src/gpu_caster_filter.hpp): each texel the
// largest of the 2 × 2 texels below it (clamped at an odd edge), so a caster can be tested
// against a few texels of the level where its footprint spans at most four.
layout(local_size_x = 8, local_size_y = 8) in;
layout(r32ui, binding = 0) readonly uniform uimage2D uFiner;
layout(r32ui, binding = 1) writeonly uniform uimage2D uCoarser;

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy), coarse = imageSize(uCoarser), fine = imageSize(uFiner) - 1;
  if (p.x >= coarse.x || p.y >= coarse.y) return;
  ivec2 q = 2 * p;
  uint m = max(max(imageLoad(uFiner, min(q, fine)).r, imageLoad(uFiner, min(q + ivec2(1, 0), fine)).r),
               max(imageLoad(uFiner, min(q + ivec2(0, 1), fine)).r, imageLoad(uFiner, min(q + ivec2(1, 1), fine)).r));
  imageStore(uCoarser, p, uvec4(m));
}
