#version 450 core
// Terrain surface: grass on gentle slopes, rock on steep ones. Outputs (one per program):
//   lit (default)   — Lambert diffuse plus a weak global ambient (thesis §6.2), no shadows;
//   OUTPUT_GBUFFER  — the geometry pass's G-buffer (gbuffer.frag);
//   OUTPUT_ID       — the tile's object ID;
//   OUTPUT_LIGHT_DEPTH — linear light depth for TSM (light_depth.frag);
//   OUTPUT_POSITION — the world-space position (tests compare it with the CPU twin).
in vec3 vNormal;
in vec3 vWorldPosition;
in vec3 vRelativePosition;
flat in uint vObjectId;

// The sun: the view block (view_block.glsl); uAlbedo: set once (the terrain's settings).
uniform vec3 uAlbedo;

#if defined(OUTPUT_GBUFFER)
void writeGBuffer(vec3 albedo, vec3 shadingNormal, vec3 relativePosition, uint objectId);
#elif defined(OUTPUT_ID)
out uint fragId;
#elif defined(OUTPUT_LIGHT_DEPTH)
void writeLightDepth(vec3 relativePosition);
#else
out vec4 fragColor;
#endif

vec3 terrainAlbedo(vec3 n) { return mix(vec3(0.42, 0.40, 0.37), uAlbedo, smoothstep(0.70, 0.85, n.y)); }

void main() {
  vec3 n = normalize(vNormal);
#if defined(OUTPUT_GBUFFER)
  writeGBuffer(terrainAlbedo(n), n, vRelativePosition, vObjectId);
#elif defined(OUTPUT_ID)
  fragId = vObjectId;
#elif defined(OUTPUT_LIGHT_DEPTH)
  writeLightDepth(vRelativePosition);
#elif defined(OUTPUT_POSITION)
  fragColor = vec4(vWorldPosition, 1.0);
#else
  float ambient = uView.toSunAmbient.w;
  float diffuse = max(dot(n, uView.toSunAmbient.xyz), 0.0);
  vec3 linear = terrainAlbedo(n) * (ambient + (1.0 - ambient) * diffuse * uView.sunColorSlopeBias.rgb);
  fragColor = vec4(pow(linear, vec3(1.0 / 2.2)), 1.0);
#endif
}
