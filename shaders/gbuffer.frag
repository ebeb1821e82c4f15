#version 450 core
// G-buffer outputs of the geometry pass, shared by the terrain, tree and prop shaders (linked in
// with them): albedo, shading normal and geometric normal (world space), object ID. The geometric
// normal is the plane of the drawn triangle, from the screen derivatives of the camera-relative
// position; the shadow term is forced to 0 where it faces away from the sun (DESIGN §4).
layout(location = 0) out vec4 gAlbedo;
layout(location = 1) out vec4 gShadingNormal;
layout(location = 2) out vec4 gGeometricNormal;
layout(location = 3) out uint gObjectId;

void writeGBuffer(vec3 albedo, vec3 shadingNormal, vec3 relativePosition, uint objectId) {
  vec3 geometric = normalize(cross(dFdx(relativePosition), dFdy(relativePosition)));
  if (dot(geometric, relativePosition) > 0.0) geometric = -geometric;  // toward the eye: a front face
  gAlbedo = vec4(albedo, 1.0);
  gShadingNormal = vec4(normalize(shadingNormal), 0.0);
  gGeometricNormal = vec4(geometric, 0.0);
  gObjectId = objectId;
}
