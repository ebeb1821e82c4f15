#version 450 core
// The receiver mask on the GPU (Bittner et al. 2011 §4; render/src/gpu_caster_filter.hpp): each
// sun-facing G-buffer pixel whose eye depth the slice spans is a receiver at
// eye + z · (forward + column · right + row · up), as ReceiverPixels places it on the CPU; its
// texel of the slice's map keeps the largest map depth of its receivers (the one farthest from
// the light). Depths are in [0, 1] (clamped): non-negative floats, whose bit patterns order as
// unsigned integers do; 0 means no receiver. A receiver the map cannot place (w ≤ 0 or not finite)
// sets `everywhere`: every caster may shadow it. Receivers outside the map count at its border
// texels (lookups there are clamped).
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 5) uniform usampler2D uSurface;  // gbuffer.frag: x eye depth bits, y albedo + sun-facing flag
layout(r32ui, binding = 0) uniform uimage2D uMask;
layout(std430, binding = 4) buffer MaskFlags { uint everywhere; uint receivers; };

uniform mat4 uToClip;        // (p − eye) → the map's clip coordinates, depth zero-to-one
uniform vec4 uLightDepthRow;  // tsm: (p − eye, 1) → linear light depth in [−1, 1]
uniform int uLinearDepth;
uniform vec3 uForward, uRight, uUp;
uniform vec2 uTanHalf;        // tan(fovx / 2), tan(fovy / 2)
uniform vec2 uDepthRange;     // the slice's eye depths
uniform int uMapSize;

void main() {
  ivec2 size = textureSize(uSurface, 0), p = ivec2(gl_GlobalInvocationID.xy);
  if (p.x >= size.x || p.y >= size.y) return;
  uvec4 s = texelFetch(uSurface, p, 0);
  float z = uintBitsToFloat(s.x);
  if ((s.y >> 24) < 128u || !(z >= uDepthRange.x && z <= uDepthRange.y)) return;  // sky, turned away, another slice
  vec2 ndc = (2.0 * (vec2(p) + 0.5) / vec2(size) - 1.0) * uTanHalf;
  vec3 r = z * (uForward + ndc.x * uRight + ndc.y * uUp);
  vec4 h = uToClip * vec4(r, 1.0);
  float depth = uLinearDepth != 0 ? 0.5 * dot(uLightDepthRow, vec4(r, 1.0)) + 0.5 : h.z / h.w;
  vec2 texel = (h.xy / h.w * 0.5 + 0.5) * float(uMapSize);
  atomicAdd(receivers, 1u);
  if (!(h.w > 0.0) || isnan(depth) || isinf(depth) || any(isnan(texel)) || any(isinf(texel))) {
    atomicOr(everywhere, 1u);
    return;
  }
  ivec2 t = clamp(ivec2(floor(clamp(texel, -1.0, float(uMapSize)))), ivec2(0), ivec2(uMapSize - 1));
  imageAtomicMax(uMask, t, floatBitsToUint(clamp(depth, 0.0, 1.0)));
}
