#version 450 core
// Tree shading: Lambert from the sun plus a weak global ambient (thesis §6.2; no shadows yet).
// With TREES_OUTPUT_ID the tree's object ID is written instead (geometry pass, tests).
in vec3 vNormal;
in vec3 vAlbedo;
flat in uint vObjectId;

uniform vec3 uToSun;
uniform vec3 uSunColor;
uniform float uAmbient;

#ifdef TREES_OUTPUT_ID
out uint fragId;
#else
out vec4 fragColor;
#endif

void main() {
#ifdef TREES_OUTPUT_ID
  fragId = vObjectId;
#else
  vec3 n = normalize(vNormal);
  float diffuse = max(dot(n, uToSun), 0.0);
  vec3 linear = vAlbedo * (uAmbient + (1.0 - uAmbient) * diffuse * uSunColor);
  fragColor = vec4(pow(linear, vec3(1.0 / 2.2)), 1.0);
#endif
}
