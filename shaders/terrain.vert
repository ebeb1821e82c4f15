#version 450 core
// Terrain tile vertex (module terrain/): the CPU twin is Terrain::drawnVertex. A vertex odd at
// level uLevel slides toward its lower-index even neighbour by the morph factor k of its distance
// to the eye (CDLOD-style), so at k = 1 the tile is exactly level uLevel + 1.
layout(location = 0) in ivec2 aLocal;   // (i, j) in the tile, 0…kTileQuads
layout(location = 1) in ivec2 iTile;    // (tx, tz)

uniform sampler2D uHeights;   // R32F, one texel per sample, fetched exactly
uniform sampler2D uNormals;   // RG16 snorm: the sample normal's (x, z) (bound for the lit output only)
uniform int uTileQuads;
uniform int uLevel;
uniform float uMorphStart;    // metres; the morph toward uLevel + 1 ramps between these
uniform float uMorphEnd;
uniform float uMorphSlack;    // the ramp reaches 0 and 1 this share of its width early
uniform vec2 uOriginRelative; // world (x, z) of sample (0, 0) minus the eye's (x, z)
uniform float uEyeY;
uniform vec3 uLodEyeRelative; // the LOD's eye minus this view's eye (zero for the eye pass; the
                              // shadow pass draws the eye's LOD from the light)
uniform vec3 uEye;            // this view's eye, world
uniform float uSpacing;
uniform mat4 uViewProjectionRelative;  // (p − eye) → clip, composed in double

uniform int uTilesPerSide;
uniform uint uObjectIdBase;

out vec3 vNormal;
out vec3 vWorldPosition;
out vec3 vRelativePosition;  // to the view's origin
flat out uint vObjectId;     // uObjectIdBase + tile index

// Camera-relative position of sample s.
vec3 samplePosition(ivec2 s) {
  float h = texelFetch(uHeights, s, 0).r;
  return vec3(uOriginRelative.x + float(s.x) * uSpacing, h - uEyeY, uOriginRelative.y + float(s.y) * uSpacing);
}

// The sample's normal (Heightfield::sampleNormal: central differences, one-sided at the border),
// stored as (x, z); y > 0 for a heightfield.
vec3 sampleNormal(ivec2 s) {
  vec2 q = texelFetch(uNormals, s, 0).xy;
  return vec3(q.x, sqrt(max(1.0 - dot(q, q), 0.0)), q.y);
}

void main() {
  int step = 1 << uLevel;
  ivec2 target = aLocal - step * ((aLocal / step) & 1);  // odd at this level → one step lower
  ivec2 base = iTile * uTileQuads;
  vec3 fine = samplePosition(base + aLocal);
  vec3 coarse = samplePosition(base + target);
  float t = (length(fine - uLodEyeRelative) - uMorphStart) / (uMorphEnd - uMorphStart);
  float k = clamp(t * (1.0 + 2.0 * uMorphSlack) - uMorphSlack, 0.0, 1.0);
  // a·(1 − k) + b·k: exactly b at k = 1 (with or without FMA), so edge vertices meet.
  vec3 p = fine * (1.0 - k) + coarse * k;
  vNormal = normalize(sampleNormal(base + aLocal) * (1.0 - k) + sampleNormal(base + target) * k);
  vWorldPosition = p + uEye;
  vRelativePosition = p;
  vObjectId = uObjectIdBase + uint(iTile.y * uTilesPerSide + iTile.x);
  gl_Position = uViewProjectionRelative * vec4(p, 1.0);
}
