#version 450 core
// One triangle covering the viewport; vUv in [0, 1]² over the screen. vRay: the camera-relative
// world direction through the pixel scaled to eye depth 1 (rays · (x_ndc, y_ndc, −1), the frame
// block's, frame_block.glsl), so that a pixel at eye depth z lies at z · vRay — linear in screen
// space, hence exact when interpolated.
out vec2 vUv;
out vec3 vRay;
void main() {
  vec2 p = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);
  vUv = p;
  vec2 ndc = 2.0 * p - 1.0;
  vRay = mat3(uFrame.rays[0].xyz, uFrame.rays[1].xyz, uFrame.rays[2].xyz) * vec3(ndc, -1.0);
  gl_Position = vec4(ndc, 0.0, 1.0);
}
