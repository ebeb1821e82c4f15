#version 450 core
// G-buffer output of the geometry pass (render/src/geometry_pass.hpp: GBuffer), shared by the
// terrain, tree and prop shaders (linked in with them). One RGBA32UI target, so that the full-screen
// passes read a pixel's surface with one texel fetch (gbuffer_read.frag has the layout's readers):
//   x: eye depth in metres, as float bits (cleared to 0: nothing drawn, the sky);
//   y: albedo (rgb), unorm 8 bits each; bits 24–31 flags: bit 31 the geometric normal faces the sun,
//      bit 30 the surface is the terrain's;
//   z: the shading normal (world space) as n / 2 + 1/2, three unorm 10-bit fields (bits 0, 10, 20);
//   w: the object ID.
// The geometric normal is the plane of the drawn triangle, from the screen derivatives of the
// camera-relative position; the shadow term is forced to 0 where it faces away from the sun
// (DESIGN §4), and only that test is kept of it. The sun comes from the view block.
layout(location = 0) out uvec4 gSurface;

// A surface whose eye depth and sun-facing test the caller knows (impostor.frag: the baked point).
// `terrain`: the terrain's surface, whose terminator the half-resolution term does not keep apart
// (shadow_term.frag).
void writeGBufferSurface(vec3 albedo, vec3 shadingNormal, float eyeDepth, bool facesSun, bool terrain, uint objectId) {
  uvec3 n = uvec3(round(clamp(0.5 * normalize(shadingNormal) + 0.5, 0.0, 1.0) * 1023.0));
  uint flags = (facesSun ? 128u : 0u) | (terrain ? 64u : 0u);
  gSurface = uvec4(floatBitsToUint(eyeDepth), packUnorm4x8(vec4(albedo, 0.0)) | (flags << 24), n.x | (n.y << 10) | (n.z << 20), objectId);
}

void writeGBuffer(vec3 albedo, vec3 shadingNormal, vec3 relativePosition, bool terrain, uint objectId) {
  vec3 geometric = cross(dFdx(relativePosition), dFdy(relativePosition));
  if (dot(geometric, relativePosition) > 0.0) geometric = -geometric;  // toward the eye: a front face
  // Perspective projection: clip w is the eye depth, and gl_FragCoord.w holds 1 / w.
  writeGBufferSurface(albedo, shadingNormal, 1.0 / gl_FragCoord.w, dot(geometric, uView.toSunAmbient.xyz) > 0.0, terrain, objectId);
}
