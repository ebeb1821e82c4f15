#version 450 core
// The nearest visible depth of the frame (render/src/nearest_depth_pass.hpp): the largest
// reversed-Z depth of the G-buffer (0 where nothing was drawn). Each invocation reads a 4×4 block,
// each work group reduces its 32×32 pixels in shared memory, then one atomic per group. Depths are
// non-negative floats, whose bit patterns order as unsigned integers do.
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 5) uniform sampler2D uDepth;
layout(std430, binding = 0) buffer Nearest { uint nearestBits; };

shared uint groupNearest;

void main() {
  if (gl_LocalInvocationIndex == 0u) groupNearest = 0u;
  barrier();
  ivec2 size = textureSize(uDepth, 0), base = ivec2(gl_GlobalInvocationID.xy) * 4;
  float nearest = 0.0;
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x) {
      ivec2 p = base + ivec2(x, y);
      if (p.x < size.x && p.y < size.y) nearest = max(nearest, texelFetch(uDepth, p, 0).r);
    }
  atomicMax(groupNearest, floatBitsToUint(nearest));
  barrier();
  if (gl_LocalInvocationIndex == 0u) atomicMax(nearestBits, groupNearest);
}
