#pragma once
// Draws the terrain (module terrain/) on the GPU: one R32F height texture, one shared local grid
// of (kTileQuads + 1)² vertices, one index range per LOD level, and per level one instanced draw
// of the tiles at that level. terrain.vert places and morphs each vertex exactly as
// Terrain::drawnVertex does on the CPU (camera-relative float positions).
#include <array>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "forest/core/camera.hpp"
#include "forest/core/scene.hpp"
#include "forest/gl/objects.hpp"
#include "forest/gl/stream_ring.hpp"
#include "forest/gl/uniform_stream.hpp"
#include "forest/gl/shader.hpp"
#include "forest/render/draw_view.hpp"
#include "forest/terrain/terrain.hpp"

namespace forest::render {

class TerrainRenderer {
 public:
  // Lit: Lambert + ambient, grass blending to rock on steep slopes. WorldPosition: writes the
  // world-space position of the drawn surface to colour (a float target; tests, ground truth).
  // ObjectId: writes objectIdBase + tile index to a GL_R32UI colour target. GBuffer: the geometry
  // pass's outputs (gbuffer.frag). LightDepth: the TSM shadow pass (light_depth.frag). BlockId:
  // objectIdBase + 16 · tile + block (terrain::Terrain::blockBoxes' numbering) to a GL_R32UI
  // target, for tiles drawn by blocks (drawBlocks; a whole tile's draw writes block 0): which
  // blocks have a pixel (forest bench culling's oracle).
  enum class Output { Lit, WorldPosition, ObjectId, GBuffer, LightDepth, BlockId };

  explicit TerrainRenderer(const terrain::Terrain& terrain, Output output = Output::Lit, std::uint32_t objectIdBase = 1);

  struct Stats {
    int tiles = 0;
    long long triangles = 0;
    std::array<int, terrain::kLevels> tilesPerLevel{};
  };
  // Draws `tiles` (indices into the terrain's tiles) into the bound framebuffer as `camera`
  // sees them, each at the level and morph the LOD gives it — the LOD may belong to another
  // camera (depth test GL_GREATER: reversed-Z).
  Stats draw(const Camera& camera, const terrain::TerrainLod& lod, const SunSettings& sun,
             std::span<const int> tiles) const;
  // The same from any view — e.g. the light's in the shadow pass, which draws the eye's LOD.
  Stats draw(const DrawView& view, const terrain::TerrainLod& lod, std::span<const int> tiles) const;
  // Blocks of tiles, each at its `level` (the one the LOD gives its tile), one instanced draw per
  // level (terrain::blockGridIndices, offset by the block's origin in terrain.vert): the shadow
  // pass's terrain casters. A block asked for a span of its cells (TileBlock::cells) draws that
  // index range alone (one multi-draw for all such). Stats count blocks and spans as tiles.
  Stats drawBlocks(const DrawView& view, const terrain::TerrainLod& lod, std::span<const terrain::TileBlock> blocks) const;
  // Occlusion queries with the tiles' own triangles (OcclusionCuller's geometry queries), tile i
  // into query slot slots[i], each at the level and morph the LOD gives it — the same surface
  // draw() makes, so a query is exactly as conservative as the depth test.
  Stats drawQueries(const DrawView& view, const terrain::TerrainLod& lod, std::span<const int> tiles,
                    std::span<const std::uint32_t> slots) const;
  // The same for blocks (whole ones; drawBlocks' surface), block i into slot slots[i]
  // (render::TerrainBlockVisibility's queries).
  Stats drawBlockQueries(const DrawView& view, const terrain::TerrainLod& lod, std::span<const terrain::TileBlock> blocks,
                         std::span<const std::uint32_t> slots) const;
  // The ground cover the lit and G-buffer materials read (terrain.frag): a side × side grid of the
  // forest's stand density D in [0, 1] over the terrain (StandField::densityGrid), row by row,
  // filtered linearly. Forest floor where D is high, meadow where it is low; without a call the
  // ground is meadow everywhere (and the material reads no cover).
  void setGroundCover(std::span<const float> cover, int side);
  // Tiles whose boxes meet the camera's frustum.
  std::vector<int> tilesInFrustum(const Camera& camera) const;

  std::size_t gpuBytes() const;

 private:
  void setProgramConstants(const gl::Program& program) const;  // the uniforms that do not change with the view
  const gl::Program& queryProgram() const;                      // loaded at the first query
  // A block's instance (tx, tz, level, block origin), checked; throws naming `caller`.
  glm::ivec4 blockInstance(const terrain::TileBlock& b, const char* caller) const;
  // A query instance's level with its slot packed above it (terrain.vert unpacks both); throws
  // naming `caller` when the slot does not fit.
  static int levelWithSlot(int level, std::uint32_t slot, const char* caller);
  const terrain::Terrain& terrain_;
  std::uint32_t objectIdBase_;
  Output output_;
  gl::Program program_;
  mutable std::optional<gl::Program> queryProgram_;  // SurfaceOutput::QueryStamp, loaded at the first query
  mutable gl::UniformStream viewUniforms_;         // ViewBlock at binding 0
  mutable gl::UniformStream terrainViewUniforms_;  // terrain.vert's TerrainViewBlock at binding 1
  gl::Texture heights_;
  gl::Texture normals_;  // vertex normals of the lit and G-buffer outputs (empty for the others)
  gl::Texture cover_;    // the ground cover, R16F (none until setGroundCover: meadow)
  gl::VertexArray vertexArray_;
  gl::Buffer grid_;
  gl::Buffer indices_;
  // Tile instances, written once per draw into a persistently mapped ring (DESIGN §9): each draw
  // addresses its part by base instance; nothing the GPU may still read is rewritten.
  std::unique_ptr<gl::StreamRing> instances_;
  // The instances in byLevel_, one instanced draw per level of the tile or the block grid.
  Stats drawByLevel(const DrawView& view, const terrain::TerrainLod& lod, bool blocks, const gl::Program& program) const;

  // Per-draw scratch, kept so the per-leaf draws of the culling traversal do not allocate.
  mutable std::array<std::vector<glm::ivec4>, terrain::kLevels> byLevel_;  // (tx, tz, level, block origin)
  struct IndirectCommand {  // glMultiDrawElementsIndirect's
    GLuint count, instanceCount, firstIndex;
    GLint baseVertex;
    GLuint baseInstance;
  };
  std::unique_ptr<gl::StreamRing> commands_;  // the blocks drawn in part, as indirect commands
  struct PartBlock {
    glm::ivec4 instance;
    terrain::CellSpan cells;  // within the block's cells
  };
  mutable std::vector<PartBlock> partBlocks_;  // drawBlocks' blocks with a span of their cells
  mutable std::vector<glm::ivec4> packed_;
  // Index ranges per level: the whole tile's grid, and block 0's.
  std::array<int, terrain::kLevels> indexOffset_{}, indexCount_{}, blockIndexOffset_{}, blockIndexCount_{};
};

}  // namespace forest::render
