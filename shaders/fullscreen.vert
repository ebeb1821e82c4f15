#version 450 core
// One triangle covering the viewport; vUv in [0, 1]² over the screen.
out vec2 vUv;
void main() {
  vec2 p = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);
  vUv = p;
  gl_Position = vec4(2.0 * p - 1.0, 0.0, 1.0);
}
