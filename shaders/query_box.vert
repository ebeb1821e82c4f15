#version 450 core
// Occlusion-query box: the unit cube scaled to the instance's [min, max] (camera-relative), depth
// only; the boxes of consecutive queries go out in one instanced draw, each instance carrying its
// query's result slot (QueryBatches::drawBatch).
layout(location = 0) in vec3 aUnit;
layout(location = 1) in vec3 iMin;
layout(location = 2) in vec3 iMax;
layout(location = 3) in uint iSlot;
// uQuery: the culler's query block (query_block.glsl).
flat out uint vSlot;
void main() {
  vSlot = iSlot;
  gl_Position = uQuery.viewProjectionRelative * vec4(mix(iMin, iMax, aUnit), 1.0);
}
