#version 450 core
// Occlusion-query box: the unit cube scaled to the instance's [min, max] (camera-relative), depth
// only; one instanced draw per query (a multiquery's boxes are its instances).
layout(location = 0) in vec3 aUnit;
layout(location = 1) in vec4 iMin;
layout(location = 2) in vec4 iMax;
// Written once per cull (OcclusionCuller, std140, binding 3): (p − eye) → clip, composed in double.
layout(std140, binding = 3) uniform QueryViewBlock { mat4 viewProjectionRelative; } uQuery;
void main() { gl_Position = uQuery.viewProjectionRelative * vec4(mix(iMin.xyz, iMax.xyz, aUnit), 1.0); }
