#version 450 core
// A screen rectangle uRect = (x0, y0, x1, y1) in NDC as a 4-vertex strip; vUv (0, 0) at the
// image's top-left (its first row).
uniform vec4 uRect;
out vec2 vUv;
void main() {
  vec2 corner = vec2(gl_VertexID & 1, gl_VertexID >> 1);
  vUv = vec2(corner.x, 1.0 - corner.y);
  gl_Position = vec4(mix(uRect.xy, uRect.zw, corner), 0.0, 1.0);
}
