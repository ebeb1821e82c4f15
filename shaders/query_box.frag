#version 450 core
// An occlusion query's result without a query object (OcclusionCuller): the depth test runs before
// this shader (early fragment tests), so it runs only for the box's fragments that pass — the
// samples GL_SAMPLES_PASSED would count — and each one marks the query's slot with the frame's
// stamp. Zero passing fragments leave the slot as it was: hidden.
layout(early_fragment_tests) in;
// uQuery: the culler's query block (query_block.glsl).
layout(std430, binding = 2) buffer QueryResults { uint stamps[]; };
flat in uint vSlot;
void main() { stamps[vSlot] = uQuery.frameStamp.x; }
