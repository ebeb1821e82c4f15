#version 450 core
// A far tree's impostor (render/impostor_atlas.hpp; TreeRenderer draws it in place of the mesh):
// one quad in the plane of the bake view nearest the viewer — the eye, or the sun in a shadow pass
// (view_block.glsl: viewer) — placed where that view's bake plane touches the tree's sphere on the
// viewer's side, so each texel shows its baked surface point moved toward the viewer; impostor.frag
// moves it back. Instance attributes as trees.vert's; no wind sway (a far tree's sway is
// sub-pixel).
layout(location = 0) in vec3 aPosition;       // the quad's corner: x, y in {−1, 1}
layout(location = 3) in vec4 iBaseScale;      // xyz: base − view origin; w: scale
layout(location = 4) in vec4 iRotationShear;  // xy: cos and sin of the yaw
layout(location = 5) in vec4 iTint;
layout(location = 6) in uint iObjectId;
layout(location = 7) in uvec2 iFadeSpecies;   // x: the cross-fade's share as float bits (1: all impostor); y: the species

out vec2 vTexel;          // texel coordinates in the species' layer
out vec3 vQuad;           // the quad's point, relative to the view's origin
flat out vec3 vToViewer;  // the bake view's direction toward the viewer, world
flat out vec4 vBaseScale;
flat out vec2 vYaw;       // cos, sin
flat out vec3 vTint;
flat out uint vObjectId;
flat out uint vSpecies;
flat out float vFade;

// vegetation/impostor_views.cpp: a direction with y ≥ 0 → its point of the square [−1, 1]², and back.
vec2 hemiOctahedral(vec3 d) {
  d.y = max(d.y, 0.0);
  d /= max(abs(d.x) + d.y + abs(d.z), 1e-20);
  return vec2(d.x + d.z, d.x - d.z);
}
vec3 fromHemiOctahedral(vec2 s) {
  float x = 0.5 * (s.x + s.y), z = 0.5 * (s.x - s.y);
  return normalize(vec3(x, max(0.0, 1.0 - abs(x) - abs(z)), z));
}
// ImpostorGrid::cellOf and ::frame.
ivec2 impostorCell(vec3 direction) {
  int views = uImpostor.grid.x;
  return clamp(ivec2(floor((hemiOctahedral(direction) + 1.0) * 0.5 * float(views))), ivec2(0), ivec2(views - 1));
}
void impostorFrame(ivec2 cell, out vec3 toViewer, out vec3 right, out vec3 up) {
  toViewer = fromHemiOctahedral(2.0 * (vec2(cell) + 0.5) / float(uImpostor.grid.x) - 1.0);
  vec3 side = cross(vec3(0.0, 1.0, 0.0), toViewer);
  right = length(side) > 1e-6 ? normalize(side) : vec3(1.0, 0.0, 0.0);
  up = cross(toViewer, right);
}

vec3 rotateYaw(vec3 p, vec2 cs) { return vec3(cs.x * p.x + cs.y * p.z, p.y, -cs.y * p.x + cs.x * p.z); }
vec3 unrotateYaw(vec3 p, vec2 cs) { return vec3(cs.x * p.x - cs.y * p.z, p.y, cs.y * p.x + cs.x * p.z); }

void main() {
  uint species = iFadeSpecies.y;
  vec4 sphere = uImpostor.sphere[species];
  float scale = iBaseScale.w;
  vec2 yaw = iRotationShear.xy;
  vec3 centre = iBaseScale.xyz + scale * rotateYaw(sphere.xyz, yaw);
  vec3 toViewer = uView.viewer.x > 0.5 ? uView.toSunAmbient.xyz : normalize(-centre);
  ivec2 cell = impostorCell(unrotateYaw(toViewer, yaw));
  vec3 t, r, u;
  impostorFrame(cell, t, r, u);
  vToViewer = rotateYaw(t, yaw);
  vQuad = centre + scale * sphere.w * rotateYaw(aPosition.x * r + aPosition.y * u + t, yaw);
  vTexel = (vec2(cell) + 0.5 * aPosition.xy + 0.5) * float(uImpostor.grid.y);
  vBaseScale = iBaseScale;
  vYaw = yaw;
  vTint = iTint.rgb;
  vObjectId = iObjectId;
  vSpecies = species;
  vFade = uintBitsToFloat(iFadeSpecies.x);
  gl_Position = uView.viewProjectionRelative * vec4(vQuad, 1.0);
}
