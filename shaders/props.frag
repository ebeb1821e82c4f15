#version 450 core
// Lambert diffuse from the sun plus a weak global ambient (thesis §6.2; no shadows yet).
in vec3 vNormal;
in vec3 vAlbedo;

uniform vec3 uToSun;     // unit vector towards the sun
uniform vec3 uSunColor;
uniform float uAmbient;

out vec4 fragColor;

void main() {
  float diffuse = max(dot(normalize(vNormal), uToSun), 0.0);
  vec3 linear = vAlbedo * (uAmbient + (1.0 - uAmbient) * diffuse * uSunColor);
  fragColor = vec4(pow(linear, vec3(1.0 / 2.2)), 1.0);  // linear → display (gamma 2.2)
}
