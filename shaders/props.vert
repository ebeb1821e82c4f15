#version 450 core
// Instanced boxes: the unit cube scaled to each instance's [min, max].
layout(location = 0) in vec3 aUnitPosition;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in vec4 iMin;
layout(location = 3) in vec4 iMax;
layout(location = 4) in vec4 iAlbedo;
layout(location = 5) in uint iObjectId;

uniform mat4 uViewProjection;

out vec3 vNormal;
out vec3 vAlbedo;
flat out uint vObjectId;

void main() {
  vec3 world = iMin.xyz + aUnitPosition * (iMax.xyz - iMin.xyz);
  vNormal = aNormal;  // axis-aligned faces: scaling keeps the normal
  vAlbedo = iAlbedo.rgb;
  vObjectId = iObjectId;
  gl_Position = uViewProjection * vec4(world, 1.0);
}
