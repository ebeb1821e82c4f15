// The occlusion culler's query block (QueryBatches::QueryView in culling/src/query_batches.hpp, std140, binding 3), written once
// per cull: (p − eye) → clip for the query boxes, composed in double; x of frameStamp: the frame's
// stamp, which a passing query fragment writes into its result slot (query_box.frag,
// query_stamp.frag).
layout(std140, binding = 3) uniform QueryViewBlock {
  mat4 viewProjectionRelative;
  uvec4 frameStamp;
} uQuery;
