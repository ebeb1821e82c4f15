#version 450 core
// Impostor bake, the viewer's side (render/src/impostor_atlas.cpp): per texel the nearest surface's
// distance s from the bake plane (metres, object space), its albedo with coverage, and its shading
// normal (object space) — packed as the atlas texel (shaders/impostor.glsl reads it):
//   x: s as float bits; y: albedo rgb and coverage (a = 1), unorm 8 bits; z: the normal as
//   n / 2 + 1/2 in three 10-bit fields; w: the far side's s (filled in by the second bake pass).
in vec3 vNormal;
in vec3 vAlbedo;
uniform float uRadius;
layout(location = 0) out uvec4 texel;

void main() {
  uvec3 n = uvec3(round(clamp(0.5 * normalize(vNormal) + 0.5, 0.0, 1.0) * 1023.0));
  texel = uvec4(floatBitsToUint(gl_FragCoord.z * 2.0 * uRadius), packUnorm4x8(vec4(vAlbedo, 1.0)), n.x | (n.y << 10) | (n.z << 20), 0u);
}
