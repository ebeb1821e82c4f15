#version 450 core
// Tree instance vertex: object → world as Forest::treeTransform does it (scale, yaw, wind shear
// about the base, translation), camera-relative.
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in vec3 aAlbedo;
layout(location = 3) in vec4 iBaseYaw;       // xyz: base − view origin; w: yaw (radians)
layout(location = 4) in vec4 iScalePhase;    // x: scale; y: sway phase
layout(location = 5) in vec4 iTint;
layout(location = 6) in uint iObjectId;

// uView: the view block (view_block.glsl), its windTime.x the time; the wind: set once.
uniform float uWindStrength;
uniform float uWindOmega;     // 2π / period
uniform vec2 uWindDirection;  // (x, z), unit

out vec3 vNormal;
out vec3 vAlbedo;
out vec3 vRelativePosition;  // to the view's origin
flat out uint vObjectId;

void main() {
  float c = cos(iBaseYaw.w), s = sin(iBaseYaw.w);
  // rotateY(yaw): x' = c x + s z, z' = −s x + c z (glm::rotate about +y).
  vec3 p = iScalePhase.x * aPosition;
  p = vec3(c * p.x + s * p.z, p.y, -s * p.x + c * p.z);
  float phase = iScalePhase.y;
  float time = uView.windTime.x;
  float sway = (sin(uWindOmega * time + phase) + 0.3 * sin(2.7 * uWindOmega * time + 1.7 * phase)) / 1.3;
  vec2 shear = uWindStrength * sway * uWindDirection;
  p.xz += shear * p.y;
  vec3 n = vec3(c * aNormal.x + s * aNormal.z, aNormal.y, -s * aNormal.x + c * aNormal.z);
  // Normals under a shear: the inverse transpose, (nx, ny − shear·n_xz, nz).
  n.y -= dot(shear, n.xz);
  vNormal = n;
  vAlbedo = aAlbedo * iTint.rgb;
  vObjectId = iObjectId;
  vRelativePosition = p + iBaseYaw.xyz;
  gl_Position = uView.viewProjectionRelative * vec4(vRelativePosition, 1.0);
}
