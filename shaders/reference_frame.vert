#version 450 core
// The reference frame's workload (forest budget, apps/forest/reference_frame.hpp), drawn without
// buffers. MESH: a GRID × GRID heightfield of two triangles per cell over the viewport, its
// vertices computed from gl_VertexID (a rolling surface, lit in the fragment program). Otherwise
// one triangle covering the viewport, for the full-screen passes.
out vec3 vNormal;
void main() {
#ifdef MESH
  int cell = gl_VertexID / 6, corner = gl_VertexID % 6;
  ivec2 offsets[6] = ivec2[6](ivec2(0, 0), ivec2(1, 0), ivec2(1, 1), ivec2(0, 0), ivec2(1, 1), ivec2(0, 1));
  vec2 uv = (vec2(cell % GRID, cell / GRID) + vec2(offsets[corner])) / float(GRID);
  float height = 0.5 + 0.25 * sin(12.0 * uv.x) * cos(9.0 * uv.y);
  vNormal = normalize(vec3(-3.0 * cos(12.0 * uv.x) * cos(9.0 * uv.y), 2.25 * sin(12.0 * uv.x) * sin(9.0 * uv.y), 1.0));
  gl_Position = vec4(2.0 * uv - 1.0, height, 1.0);
#else
  vNormal = vec3(0.0, 0.0, 1.0);
  gl_Position = vec4(2.0 * vec2((gl_VertexID << 1) & 2, gl_VertexID & 2) - 1.0, 0.0, 1.0);
#endif
}
