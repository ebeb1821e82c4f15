#version 450 core
// Linear light depth for trapezoidal shadow maps (TSM §4; DESIGN §4): the map's x, y come from the
// trapezoidal matrix, but the depth written is the uniform light map's z_L (affine in the world),
// evaluated at the fragment's interpolated position — interpolating z_L·w_T/w_L instead fails on
// large triangles. Polygon offset does not apply to gl_FragDepth, so the slope-scale bias is
// added here: factor × the depth's largest screen slope, as glPolygonOffset(factor, 0) does.
// The row (p − view origin, 1) → z_L and the bias factor: the view block (view_block.glsl).

void writeLightDepth(vec3 relativePosition) {
  float depth = 0.5 * dot(uView.lightDepthRow, vec4(relativePosition, 1.0)) + 0.5;
  float slope = max(abs(dFdx(depth)), abs(dFdy(depth)));
  gl_FragDepth = clamp(depth + uView.sunColorSlopeBias.w * slope, 0.0, 1.0);
}
