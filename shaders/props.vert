#version 450 core
// Instanced boxes: the unit cube scaled to each instance's [min, max], camera-relative.
layout(location = 0) in vec3 aUnitPosition;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in vec4 iMin;   // world
layout(location = 3) in vec4 iMax;
layout(location = 4) in vec4 iAlbedo;
layout(location = 5) in uint iObjectId;

uniform mat4 uViewProjectionRelative;
uniform vec3 uOrigin;  // the view's origin, world

out vec3 vNormal;
out vec3 vAlbedo;
out vec3 vRelativePosition;
flat out uint vObjectId;

void main() {
  vRelativePosition = mix(iMin.xyz, iMax.xyz, aUnitPosition) - uOrigin;
  vNormal = aNormal;  // axis-aligned faces: scaling keeps the normal
  vAlbedo = iAlbedo.rgb;
  vObjectId = iObjectId;
  gl_Position = uViewProjectionRelative * vec4(vRelativePosition, 1.0);
}
