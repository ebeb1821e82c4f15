#version 450 core
// Tree surface: per-vertex albedo times the tree's tint. Outputs (one per program): lit (Lambert
// plus a weak global ambient, thesis §6.2, no shadows), OUTPUT_GBUFFER (gbuffer.frag), OUTPUT_ID,
// OUTPUT_LIGHT_DEPTH (light_depth.frag), OUTPUT_QUERY_STAMP (query_stamp.frag; the ID is a slot).
in vec3 vNormal;
in vec3 vAlbedo;
in vec3 vRelativePosition;
flat in uint vObjectId;
#if defined(CROSS_FADE)
flat in float vFade;  // the impostor's share: the mesh keeps the pixels the impostor leaves (impostor.glsl)
#endif

// The sun: the view block (view_block.glsl).

#if defined(OUTPUT_GBUFFER)
void writeGBuffer(vec3 albedo, vec3 shadingNormal, vec3 relativePosition, bool terrain, uint objectId);
#elif defined(OUTPUT_ID)
out uint fragId;
#elif defined(OUTPUT_LIGHT_DEPTH)
void writeLightDepth(vec3 relativePosition);
#elif defined(OUTPUT_QUERY_STAMP)
void writeQueryStamp(uint slot);
#else
out vec4 fragColor;
#endif

void main() {
#if defined(CROSS_FADE)
  if (crossFadeDither(gl_FragCoord.xy) < vFade) discard;
#endif
#if defined(OUTPUT_GBUFFER)
  writeGBuffer(vAlbedo, vNormal, vRelativePosition, false, vObjectId);
#elif defined(OUTPUT_ID)
  fragId = vObjectId;
#elif defined(OUTPUT_LIGHT_DEPTH)
  writeLightDepth(vRelativePosition);
#elif defined(OUTPUT_QUERY_STAMP)
  writeQueryStamp(vObjectId);
#else
  vec3 n = normalize(vNormal);
  float ambient = uView.toSunAmbient.w;
  float diffuse = max(dot(n, uView.toSunAmbient.xyz), 0.0);
  vec3 linear = vAlbedo * (ambient + (1.0 - ambient) * diffuse * uView.sunColorSlopeBias.rgb);
  fragColor = vec4(pow(linear, vec3(1.0 / 2.2)), 1.0);
#endif
}
