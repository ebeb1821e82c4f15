#version 450 core
// Lambert diffuse from the sun plus a weak global ambient (thesis §6.2; no shadows yet). With
// PROPS_OUTPUT_ID the prop's object ID is written instead (geometry pass).
in vec3 vNormal;
in vec3 vAlbedo;
flat in uint vObjectId;

uniform vec3 uToSun;     // unit vector towards the sun
uniform vec3 uSunColor;
uniform float uAmbient;

#ifdef PROPS_OUTPUT_ID
out uint fragId;
#else
out vec4 fragColor;
#endif

void main() {
#ifdef PROPS_OUTPUT_ID
  fragId = vObjectId;
#else
  float diffuse = max(dot(normalize(vNormal), uToSun), 0.0);
  vec3 linear = vAlbedo * (uAmbient + (1.0 - uAmbient) * diffuse * uSunColor);
  fragColor = vec4(pow(linear, vec3(1.0 / 2.2)), 1.0);  // linear → display (gamma 2.2)
#endif
}
