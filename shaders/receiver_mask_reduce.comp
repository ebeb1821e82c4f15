#version 450 core
// One level of the receiver mask's pyramid (render/src/gpu_caster_filter.hpp): each texel the
// largest of the 2 × 2 texels below it — the last column and row also of the third where the level
// below has an odd size (a level is half the one below, rounded down, so texel t of level 0 lies
// in texel min(t >> k, size_k − 1) of level k) — so a caster can be tested against a few texels
// of the level where its footprint spans at most four.
layout(local_size_x = 8, local_size_y = 8) in;
layout(r32ui, binding = 0) readonly uniform uimage2D uFiner;
layout(r32ui, binding = 1) writeonly uniform uimage2D uCoarser;

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy), coarse = imageSize(uCoarser), fine = imageSize(uFiner) - 1;
  if (p.x >= coarse.x || p.y >= coarse.y) return;
  ivec2 q = 2 * p, last = min(q + 1 + ivec2(equal(p, coarse - 1)), fine);
  uint m = 0u;
  for (int y = q.y; y <= last.y; ++y)
    for (int x = q.x; x <= last.x; ++x) m = max(m, imageLoad(uFiner, ivec2(x, y)).r);
  imageStore(uCoarser, p, uvec4(m));
}
