#version 450 core
// Instanced boxes: the unit cube scaled to each instance's [min, max], given relative to the
// view's origin (subtracted in double on the CPU: DESIGN §4).
layout(location = 0) in vec3 aUnitPosition;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in vec4 iMin;   // relative to the view's origin
layout(location = 3) in vec4 iMax;
layout(location = 4) in vec4 iAlbedo;
layout(location = 5) in uint iObjectId;

// uView: the view block (view_block.glsl).

out vec3 vNormal;
out vec3 vAlbedo;
out vec3 vRelativePosition;
flat out uint vObjectId;

void main() {
  vRelativePosition = mix(iMin.xyz, iMax.xyz, aUnitPosition);
  vNormal = aNormal;  // axis-aligned faces: scaling keeps the normal
  vAlbedo = iAlbedo.rgb;
  vObjectId = iObjectId;
  gl_Position = uView.viewProjectionRelative * vec4(vRelativePosition, 1.0);
}
