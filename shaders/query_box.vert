#version 450 core
// Occlusion-query box: the unit cube scaled to [uMin, uMax] (camera-relative), depth only.
layout(location = 0) in vec3 aUnit;
uniform vec3 uMin;
uniform vec3 uMax;
uniform mat4 uViewProjectionRelative;
void main() { gl_Position = uViewProjectionRelative * vec4(mix(uMin, uMax, aUnit), 1.0); }
