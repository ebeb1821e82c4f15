#version 450 core
// Prop boxes. Outputs (one per program): lit (Lambert plus a weak global ambient, thesis §6.2, no
// shadows), OUTPUT_GBUFFER (gbuffer.frag), OUTPUT_ID.
in vec3 vNormal;
in vec3 vAlbedo;
in vec3 vRelativePosition;
flat in uint vObjectId;

// The sun: the view block (view_block.glsl).

#if defined(OUTPUT_GBUFFER)
void writeGBuffer(vec3 albedo, vec3 shadingNormal, vec3 relativePosition, bool terrain, uint objectId);
#elif defined(OUTPUT_ID)
out uint fragId;
#elif defined(OUTPUT_LIGHT_DEPTH)
void writeLightDepth(vec3 relativePosition);
#else
out vec4 fragColor;
#endif

void main() {
#if defined(OUTPUT_GBUFFER)
  writeGBuffer(vAlbedo, vNormal, vRelativePosition, false, vObjectId);
#elif defined(OUTPUT_ID)
  fragId = vObjectId;
#elif defined(OUTPUT_LIGHT_DEPTH)
  writeLightDepth(vRelativePosition);
#else
  float ambient = uView.toSunAmbient.w;
  float diffuse = max(dot(normalize(vNormal), uView.toSunAmbient.xyz), 0.0);
  vec3 linear = vAlbedo * (ambient + (1.0 - ambient) * diffuse * uView.sunColorSlopeBias.rgb);
  fragColor = vec4(pow(linear, vec3(1.0 / 2.2)), 1.0);  // linear → display (gamma 2.2)
#endif
}
