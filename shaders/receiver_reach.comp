#version 450 core
// The texels the receivers' lookups read (render/src/gpu_caster_filter.hpp): per texel, the
// farthest receiver within uRadius texels along uAxis — run along x, then y, over the receiver
// mask's level 0, it gives for each texel the farthest receiver whose lookup may read it (0: none).
layout(local_size_x = 8, local_size_y = 8) in;
layout(r32ui, binding = 0) readonly uniform uimage2D uFrom;
layout(r32ui, binding = 1) writeonly uniform uimage2D uTo;
uniform ivec2 uAxis;
uniform int uRadius;

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy), size = imageSize(uTo);
  if (p.x >= size.x || p.y >= size.y) return;
  uint farthest = 0u;
  for (int k = -uRadius; k <= uRadius; ++k) farthest = max(farthest, imageLoad(uFrom, clamp(p + k * uAxis, ivec2(0), size - 1)).r);
  imageStore(uTo, p, uvec4(farthest));
}
