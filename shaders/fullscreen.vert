#version 450 core
// One triangle covering the viewport. vRay: the camera-relative world direction through the pixel
// scaled to eye depth 1 (rays · (x_ndc, y_ndc, −1), the frame block's, frame_block.glsl), so that a
// pixel at eye depth z lies at z · vRay — linear in screen space, hence exact when interpolated.
// In the shadow lookup's programs (SHADOW_SLICES defined, shadow_lookup.frag), the same holds in
// each slice's shadow clip space: with M the slice's eye-relative light matrix,
// M · (z · vRay, 1) = z · vShadowRay + M[3], vShadowRay = M · (vRay, 0); and for tsm's linear
// light depth row r, r · (z · vRay, 1) = z · vLightDepthRay + r.w. Interpolated, they spare each
// pixel a 4 × 4 product.
out vec3 vRay;
#ifdef SHADOW_SLICES
out vec4 vShadowRay[SHADOW_SLICES];
out float vLightDepthRay[SHADOW_SLICES];
#endif
void main() {
  vec2 ndc = 2.0 * vec2((gl_VertexID << 1) & 2, gl_VertexID & 2) - 1.0;
  vRay = mat3(uFrame.rays[0].xyz, uFrame.rays[1].xyz, uFrame.rays[2].xyz) * vec3(ndc, -1.0);
#ifdef SHADOW_SLICES
  for (int i = 0; i < SHADOW_SLICES; ++i) {
    vShadowRay[i] = uFrame.eyeRelativeToShadow[i] * vec4(vRay, 0.0);
    vLightDepthRay[i] = dot(uFrame.eyeRelativeLightDepth[i].xyz, vRay);
  }
#endif
#if defined(AT_HALF_TERM_DEPTH)  // the lighting's draws either side of that depth (render/src/lighting_pass.cpp)
  gl_Position = vec4(ndc, uFrame.halfTerm.x, 1.0);
#elif defined(AT_HALF_TERM_REACH)  // the half-resolution passes, nearer than what lighting reads (shadow_term_pass.cpp)
  gl_Position = vec4(ndc, uFrame.halfTerm.y, 1.0);
#else
  gl_Position = vec4(ndc, 0.0, 1.0);  // the reversed-Z clear value: the sky's
#endif
}
