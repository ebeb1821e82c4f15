#version 450 core
// Terrain tile vertex (module terrain/): the CPU twin is Terrain::drawnVertex. A vertex odd at
// level L (the tile's) slides toward its lower-index even neighbour by the morph factor k of its
// distance to the eye (CDLOD-style), so at k = 1 the tile is exactly level L + 1.
layout(location = 0) in ivec2 aLocal;   // (i, j) in the tile, 0…kTileQuads
layout(location = 1) in ivec4 iTile;    // (tx, tz, level L, block origin): the origin's (i, j) in
                                        // the tile as i + 256 j (0 for a whole tile; a block is
                                        // drawn with blockGridIndices, TerrainRenderer::drawBlocks)

// Per view and level of detail (TerrainRenderer, std140, binding 1), written once per pass;
// uView (view_block.glsl) holds the view-projection.
layout(std140, binding = 1) uniform TerrainViewBlock {
  vec4 originRelative;  // x, z: world (x, z) of sample (0, 0) minus the eye's (x, z); y: the eye's y
  vec4 eye;             // xyz: this view's eye, world
  vec4 lodEyeRelative;  // xyz: the LOD's eye minus this view's eye (zero for the eye pass; the
                        // shadow pass draws the eye's LOD from the light)
  vec4 morph[TERRAIN_LEVELS];  // per level: x, y = metres where the morph toward level + 1 starts, ends
} uTerrain;

// Set once, at construction.
layout(binding = 0) uniform sampler2D uHeights;   // R32F, one texel per sample, fetched exactly
layout(binding = 1) uniform sampler2D uNormals;   // RG16 snorm: the sample normal's (x, z) (lit outputs only)
uniform int uTileQuads;
uniform float uMorphSlack;    // the ramp reaches 0 and 1 this share of its width early
uniform float uSpacing;
uniform int uTilesPerSide;
uniform uint uObjectIdBase;

out vec3 vNormal;
out vec3 vWorldPosition;
out vec3 vRelativePosition;  // to the view's origin
flat out uint vObjectId;     // uObjectIdBase + tile index (a query: its slot)

// Camera-relative position of sample s.
vec3 samplePosition(ivec2 s) {
  float h = texelFetch(uHeights, s, 0).r;
  vec4 origin = uTerrain.originRelative;
  return vec3(origin.x + float(s.x) * uSpacing, h - origin.y, origin.z + float(s.y) * uSpacing);
}

// The sample's normal (Heightfield::sampleNormal: central differences, one-sided at the border),
// stored as (x, z); y > 0 for a heightfield.
vec3 sampleNormal(ivec2 s) {
  vec2 q = texelFetch(uNormals, s, 0).xy;
  return vec3(q.x, sqrt(max(1.0 - dot(q, q), 0.0)), q.y);
}

void main() {
#ifdef OUTPUT_QUERY_STAMP
  // TerrainRenderer::drawQueries packs the tile's query slot above its level.
  int level = iTile.z & ((1 << QUERY_SLOT_SHIFT) - 1);
#else
  int level = iTile.z;
#endif
  int step = 1 << level;
  ivec2 local = aLocal + ivec2(iTile.w & 255, iTile.w >> 8);
  ivec2 target = local - step * ((local / step) & 1);  // odd at this level → one step lower
  ivec2 base = iTile.xy * uTileQuads;
  vec3 fine = samplePosition(base + local);
  vec3 coarse = samplePosition(base + target);
  vec2 morph = uTerrain.morph[level].xy;
  float t = (length(fine - uTerrain.lodEyeRelative.xyz) - morph.x) / (morph.y - morph.x);
  float k = clamp(t * (1.0 + 2.0 * uMorphSlack) - uMorphSlack, 0.0, 1.0);
  // a·(1 − k) + b·k: exactly b at k = 1 (with or without FMA), so edge vertices meet.
  vec3 p = fine * (1.0 - k) + coarse * k;
  vNormal = normalize(sampleNormal(base + local) * (1.0 - k) + sampleNormal(base + target) * k);
  vWorldPosition = p + uTerrain.eye.xyz;
  vRelativePosition = p;
#ifdef OUTPUT_QUERY_STAMP
  vObjectId = uint(iTile.z >> QUERY_SLOT_SHIFT);
#elif defined(OUTPUT_BLOCK_ID)
  // TerrainRenderer::Output::BlockId, drawn by blocks (drawBlocks: the instance's block origin):
  // uObjectIdBase + tile · 16 + block, blocks row-major as terrain::blockBoxes numbers them.
  int quads = clamp(2 << level, 16, uTileQuads), perSide = uTileQuads / quads;
  ivec2 block = ivec2(iTile.w & 255, iTile.w >> 8) / quads;
  vObjectId = uObjectIdBase + uint((iTile.y * uTilesPerSide + iTile.x) * (uTileQuads / 16) * (uTileQuads / 16) + block.y * perSide + block.x);
#else
  vObjectId = uObjectIdBase + uint(iTile.y * uTilesPerSide + iTile.x);
#endif
  gl_Position = uView.viewProjectionRelative * vec4(p, 1.0);
}
