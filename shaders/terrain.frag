#version 450 core
// Terrain shading: Lambert diffuse from the sun plus a weak global ambient (thesis §6.2; no
// shadows yet); grass on gentle slopes, rock on steep ones. With TERRAIN_OUTPUT_POSITION the
// fragment's world-space position is written instead (tests compare it with the CPU twin); with
// TERRAIN_OUTPUT_ID the tile's object ID (geometry pass).
in vec3 vNormal;
in vec3 vWorldPosition;
flat in uint vObjectId;

uniform vec3 uToSun;
uniform vec3 uSunColor;
uniform float uAmbient;
uniform vec3 uAlbedo;

#ifdef TERRAIN_OUTPUT_ID
out uint fragId;
#else
out vec4 fragColor;
#endif

void main() {
#if defined(TERRAIN_OUTPUT_ID)
  fragId = vObjectId;
#elif defined(TERRAIN_OUTPUT_POSITION)
  fragColor = vec4(vWorldPosition, 1.0);
#else
  vec3 n = normalize(vNormal);
  vec3 rock = vec3(0.42, 0.40, 0.37);
  vec3 albedo = mix(rock, uAlbedo, smoothstep(0.70, 0.85, n.y));
  float diffuse = max(dot(n, uToSun), 0.0);
  vec3 linear = albedo * (uAmbient + (1.0 - uAmbient) * diffuse * uSunColor);
  fragColor = vec4(pow(linear, vec3(1.0 / 2.2)), 1.0);
#endif
}
