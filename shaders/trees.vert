#version 450 core
// Tree instance vertex: object → world as Forest::treeTransform does it (scale, yaw, wind shear
// about the base, translation), camera-relative. The instance holds the yaw's cosine and sine and
// the shear at the draw's time (TreeRenderer::InstanceGpu): no sine per vertex.
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in vec3 aAlbedo;
layout(location = 3) in vec4 iBaseScale;      // xyz: base − view origin; w: scale
layout(location = 4) in vec4 iRotationShear;  // xy: cos and sin of the yaw; zw: the wind's shear (x, z)
layout(location = 5) in vec4 iTint;
layout(location = 6) in uint iObjectId;
#if defined(CROSS_FADE)
layout(location = 7) in uvec2 iFadeSpecies;  // x: the impostor's share of the cross-fade (float bits)
flat out float vFade;
#endif

// uView: the view block (view_block.glsl).

// The same position in every program that draws trees: a geometry query (query_stamp.frag) must
// cover exactly the fragments, at exactly the depths, that the tree's draw does.
invariant gl_Position;
out vec3 vNormal;
out vec3 vAlbedo;
out vec3 vRelativePosition;  // to the view's origin
flat out uint vObjectId;

void main() {
  float c = iRotationShear.x, s = iRotationShear.y;
  // rotateY(yaw): x' = c x + s z, z' = −s x + c z (glm::rotate about +y).
  vec3 p = iBaseScale.w * aPosition;
  p = vec3(c * p.x + s * p.z, p.y, -s * p.x + c * p.z);
  vec2 shear = iRotationShear.zw;
  p.xz += shear * p.y;
  vec3 n = vec3(c * aNormal.x + s * aNormal.z, aNormal.y, -s * aNormal.x + c * aNormal.z);
  // Normals under a shear: the inverse transpose, (nx, ny − shear·n_xz, nz).
  n.y -= dot(shear, n.xz);
  vNormal = n;
  vAlbedo = aAlbedo * iTint.rgb;
  vObjectId = iObjectId;
#if defined(CROSS_FADE)
  vFade = uintBitsToFloat(iFadeSpecies.x);
#endif
  vRelativePosition = p + iBaseScale.xyz;
  gl_Position = uView.viewProjectionRelative * vec4(vRelativePosition, 1.0);
}
