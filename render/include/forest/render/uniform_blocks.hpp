#pragma once
// The uniform blocks of the shaders (std140), as C++ structs (DESIGN §9: per-frame and per-pass
// values in buffers, written once through gl::UniformStream, never set per draw). Each mirrors a
// declaration in shaders/; the test UniformBlocksMatchTheShaders asks the GL for every block's
// size and member offsets and compares them with these.
#include <glm/glm.hpp>

#include "forest/gl/objects.hpp"
#include "forest/terrain/terrain.hpp"

namespace forest::render {

// shaders/view_block.glsl, binding 0: the pass's view, read by every surface shader.
struct ViewBlock {
  glm::mat4 viewProjectionRelative{1.0f};  // (p − view origin) → clip
  glm::vec4 lightDepthRow{0.0f};           // LightDepth output: (p − view origin, 1) → z_L
  glm::vec4 toSunAmbient{0.0f};            // xyz: toward the sun; w: ambient share
  glm::vec4 sunColorSlopeBias{0.0f};       // rgb: sun colour; w: LightDepth slope-scale bias
  // x: 1 when the view is the sun's (its rays along −toSun), 0 an eye at the origin; y: +1 when the
  // pass's depth test keeps the lesser depth, −1 the greater (reversed-Z). Impostors read it.
  glm::vec4 viewer{0.0f, -1.0f, 0.0f, 0.0f};
};
constexpr GLuint kViewBlockBinding = 0;

// shaders/terrain.vert's TerrainViewBlock, binding 1: per view and level of detail.
struct TerrainViewBlock {
  glm::vec4 originRelative{0.0f};  // x, z: world (x, z) of sample (0, 0) minus the eye's; y: the eye's y
  glm::vec4 eye{0.0f};             // xyz: the view's eye, world
  glm::vec4 lodEyeRelative{0.0f};  // xyz: the LOD's eye minus the view's eye
  glm::vec4 morph[terrain::kLevels]{};  // x, y: where the morph toward the next level starts, ends (m)
};
constexpr GLuint kTerrainViewBlockBinding = 1;

// shaders/frame_block.glsl, binding 2: the full-screen passes' values, once per frame.
struct FrameBlock {
  // Per slice (cascade): (p − eye) → shadow clip, z in [0, 1], lookup shift applied; tsm's (p − eye, 1) → z_L.
  glm::mat4 eyeRelativeToShadow[4]{glm::mat4(1.0f), glm::mat4(1.0f), glm::mat4(1.0f), glm::mat4(1.0f)};
  glm::vec4 eyeRelativeLightDepth[4]{};
  glm::vec4 rays[3]{};                    // pixel rays at eye depth 1, column by column
  glm::vec4 toSunUp{0.0f};                // xyz: toward the sun; w: 1 when above the horizon
  glm::vec4 sunColorAmbient{0.0f};
  glm::vec4 skyFog{0.0f};                 // rgb: sky, linear; w: fog density per metre
  glm::vec4 blur{0.0f};                   // radius px, reference depth m, relative depth tolerance, pixels per term texel side
  glm::vec4 cascadeEnds{0.0f};            // eye depth (m) where slice 0, 1, 2, 3 ends
  glm::vec4 cascadeBlend{0.0f};           // x: the blend band's share of a split's distance
  glm::ivec4 modes{0};                    // PCF radius, tsm linear depth, slices, shadowed
  // The lighting pass's record of what shows (render/src/image_visibility.hpp): this frame's stamp
  // (0: none), tiles per side, tiles (IDs 1 to this are tiles), the first block's slot.
  glm::uvec4 imageRecord{0u};
  glm::vec4 imageTerrain{0.0f};  // the eye in terrain samples from the heightfield's origin (x, z), 1 / spacing, quads per tile
  // x: the window depth of the eye depth within which lighting upsamples the half-resolution term;
  // y: that of the eye depth up to which the blur computes it; z, w: a, b of the window depth a/z + b.
  glm::vec4 halfTerm{0.0f};
};
constexpr GLuint kFrameBlockBinding = 2;

// shaders/impostor.glsl, binding 4: the impostor bake's layout and the species' volumes, written
// once at the bake (ImpostorAtlas).
struct ImpostorBlock {
  glm::ivec4 grid{0};           // x: views a side, y: texels a view side
  glm::vec4 sphere[4]{};        // per species: bake sphere centre, radius (object space)
  glm::vec4 boxMin[4]{}, boxMax[4]{};  // per species: its box over all LODs
  glm::vec4 querySlabs[16]{};   // species s, slab k (4 a species): bottom, top, radius
  glm::vec4 casterSlabs[32]{};  // species s, slab k (8 a species): bottom, top, radius at each
};
constexpr GLuint kImpostorBlockBinding = 4;
constexpr GLuint kImpostorAtlasUnit = 9;  // impostor.frag's uImpostorAtlas

// Binding 3: culling's query_box.vert (a mat4, the camera-relative view-projection).

}  // namespace forest::render
