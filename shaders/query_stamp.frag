#version 450 core
// An occlusion query drawn with an object's own triangles (OcclusionCuller's geometry queries;
// linked with the object's surface shader, which passes the query's slot as its object ID): as
// query_box.frag, the depth test runs first (early fragment tests), and each fragment that passes
// marks the slot with the frame's stamp. The culler binds the block and the buffer.
layout(early_fragment_tests) in;
// uQuery: the culler's query block (query_block.glsl).
layout(std430, binding = 2) buffer QueryResults { uint stamps[]; };

void writeQueryStamp(uint slot) { stamps[slot] = uQuery.frameStamp.x; }
