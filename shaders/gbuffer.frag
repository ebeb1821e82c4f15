#version 450 core
// G-buffer outputs of the geometry pass (render/src/geometry_pass.hpp: GBuffer), shared by the
// terrain, tree and prop shaders (linked in with them): albedo, whether the geometric normal faces
// the sun (alpha 1 or 0), the shading normal (world space, as n / 2 + 1/2 in RGB10_A2), object ID.
// The geometric normal is the plane of the drawn triangle, from the screen derivatives of the
// camera-relative position; the shadow term is forced to 0 where it faces away from the sun
// (DESIGN §4), and only that test is kept of it. The sun comes from the view block.
layout(location = 0) out vec4 gAlbedoSunFacing;
layout(location = 1) out vec4 gShadingNormal;
layout(location = 2) out uint gObjectId;

void writeGBuffer(vec3 albedo, vec3 shadingNormal, vec3 relativePosition, uint objectId) {
  vec3 geometric = cross(dFdx(relativePosition), dFdy(relativePosition));
  if (dot(geometric, relativePosition) > 0.0) geometric = -geometric;  // toward the eye: a front face
  gAlbedoSunFacing = vec4(albedo, dot(geometric, uView.toSunAmbient.xyz) > 0.0 ? 1.0 : 0.0);
  gShadingNormal = vec4(0.5 * normalize(shadingNormal) + 0.5, 0.0);
  gObjectId = objectId;
}
