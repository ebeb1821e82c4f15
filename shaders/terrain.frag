#version 450 core
// Terrain surface, a procedural material (issue "A forest to walk through"): meadow grass that
// dries toward the heights, forest floor where the stands are (the ground cover: the stand
// density D of vegetation/stand_field.hpp), rock on steep slopes; value noise at two scales —
// patches of tens of metres, grain of a few — varies each. A pure function of the world position,
// the normal and the cover texture. Outputs (one per program):
//   lit (default)   — Lambert diffuse plus a weak global ambient (thesis §6.2), no shadows;
//   OUTPUT_GBUFFER  — the geometry pass's G-buffer (gbuffer.frag);
//   OUTPUT_ID       — the tile's object ID;
//   OUTPUT_LIGHT_DEPTH — linear light depth for TSM (light_depth.frag);
//   OUTPUT_QUERY_STAMP — an occlusion query with the tile's own triangles (query_stamp.frag);
//   OUTPUT_POSITION — the world-space position (tests compare it with the CPU twin).
in vec3 vNormal;
in vec3 vWorldPosition;
in vec3 vRelativePosition;
flat in uint vObjectId;

// The sun: the view block (view_block.glsl). Set once (TerrainRenderer):
uniform vec3 uAlbedo;               // meadow grass: the terrain's albedo setting
uniform vec2 uHeightRange;          // x: the terrain's lowest height; y: its height range (m)
#ifdef GROUND_COVER  // a forest with stands (TerrainRenderer::setGroundCover); without: meadow, no lookup
uniform vec4 uCoverOriginInvSize;   // xy: world (x, z) of the cover grid's corner; z: 1 / its size (m)
layout(binding = 2) uniform sampler2D uGroundCover;  // D in [0, 1], filtered linearly
#endif

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

const vec3 kRock = vec3(0.42, 0.40, 0.37);
const vec3 kForestFloor = vec3(0.24, 0.19, 0.11);  // needles and leaf litter
const vec3 kDryGrass = vec3(0.45, 0.42, 0.22);

// A hash of an integer lattice point to [0, 1] (integer arithmetic: the same on every GPU).
float latticeHash(ivec2 c) {
  uint h = uint(c.x) * 0x8da6b343u ^ uint(c.y) * 0xd8163841u;
  h = (h ^ (h >> 13u)) * 0x9e3779b9u;
  h ^= h >> 16u;
  return float(h & 0xffffu) / 65535.0;
}

// Value noise in [0, 1]: the lattice hashes blended by smoothstep weights.
float valueNoise(vec2 p) {
  vec2 cell = floor(p), f = p - cell, u = f * f * (3.0 - 2.0 * f);
  ivec2 c = ivec2(cell);
  return mix(mix(latticeHash(c), latticeHash(c + ivec2(1, 0)), u.x), mix(latticeHash(c + ivec2(0, 1)), latticeHash(c + ivec2(1, 1)), u.x), u.y);
}

vec3 terrainAlbedo(vec3 n, vec3 world) {
#ifdef GROUND_COVER
  float cover = texture(uGroundCover, (world.xz - uCoverOriginInvSize.xy) * uCoverOriginInvSize.z).r;
#else
  float cover = 0.0;
#endif
  float patches = valueNoise(world.xz / 40.0) - 0.5;  // tens of metres
  float grain = valueNoise(world.xz / 3.0);           // metres
  float altitude = clamp((world.y - uHeightRange.x) / uHeightRange.y, 0.0, 1.0);
  vec3 meadow = mix(uAlbedo, kDryGrass, clamp(0.35 * altitude + 0.5 * patches, 0.0, 1.0));
  vec3 ground = mix(meadow, kForestFloor, smoothstep(0.25, 0.75, cover + 0.3 * patches));
  float rocky = 1.0 - smoothstep(0.70, 0.85, n.y + 0.1 * patches);
  return mix(ground, kRock * (1.0 + 0.3 * patches), rocky) * (0.85 + 0.3 * grain);
}

void main() {
  vec3 n = normalize(vNormal);
#if defined(OUTPUT_GBUFFER)
  writeGBuffer(terrainAlbedo(n, vWorldPosition), n, vRelativePosition, true, vObjectId);
#elif defined(OUTPUT_ID)
  fragId = vObjectId;
#elif defined(OUTPUT_LIGHT_DEPTH)
  writeLightDepth(vRelativePosition);
#elif defined(OUTPUT_QUERY_STAMP)
  writeQueryStamp(vObjectId);
#elif defined(OUTPUT_POSITION)
  fragColor = vec4(vWorldPosition, 1.0);
#else
  float ambient = uView.toSunAmbient.w;
  float diffuse = max(dot(n, uView.toSunAmbient.xyz), 0.0);
  vec3 linear = terrainAlbedo(n, vWorldPosition) * (ambient + (1.0 - ambient) * diffuse * uView.sunColorSlopeBias.rgb);
  fragColor = vec4(pow(linear, vec3(1.0 / 2.2)), 1.0);
#endif
}
