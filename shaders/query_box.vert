#version 450 core
// Occlusion-query box: the unit cube scaled to the instance's [min, max] (camera-relative), depth
// only; the boxes of consecutive queries go out in one instanced draw, each instance carrying its
// query's result slot (OcclusionCuller::drawQueryBatch).
layout(location = 0) in vec3 aUnit;
layout(location = 1) in vec3 iMin;
layout(location = 2) in vec3 iMax;
layout(location = 3) in uint iSlot;
// Written once per cull (OcclusionCuller, std140, binding 3): (p − eye) → clip, composed in
// double; x of frameStamp: the frame's stamp, which query_box.frag writes.
layout(std140, binding = 3) uniform QueryViewBlock {
  mat4 viewProjectionRelative;
  uvec4 frameStamp;
} uQuery;
flat out uint vSlot;
void main() {
  vSlot = iSlot;
  gl_Position = uQuery.viewProjectionRelative * vec4(mix(iMin, iMax, aUnit), 1.0);
}
