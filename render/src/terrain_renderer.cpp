#include "forest/render/terrain_renderer.hpp"

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "forest/core/error.hpp"
#include "forest/core/frustum.hpp"

namespace forest::render {
namespace {

using terrain::kLevels;
using terrain::kTileQuads;

// drawQueries' instances carry the query slot above the level: (level | slot << shift).
constexpr int kQuerySlotShift = 4;
static_assert(kLevels <= (1 << kQuerySlotShift), "the level must fit below the query slot");
constexpr std::uint32_t kMaxQuerySlot = (1u << (31 - kQuerySlotShift)) - 1u;

// `groundCover`: the material reads the ground cover texture (GROUND_COVER; without it, meadow).
gl::Program loadTerrainProgram(TerrainRenderer::Output output, bool groundCover = false) {
  const std::string levels =
      "#define TERRAIN_LEVELS " + std::to_string(kLevels) + "\n" + (groundCover ? "#define GROUND_COVER 1\n" : "");
  switch (output) {
    case TerrainRenderer::Output::WorldPosition:
      return loadSurfaceProgram("terrain.vert", "terrain.frag", SurfaceOutput::Lit, levels + "#define OUTPUT_POSITION 1\n");
    case TerrainRenderer::Output::ObjectId: return loadSurfaceProgram("terrain.vert", "terrain.frag", SurfaceOutput::ObjectId, levels);
    case TerrainRenderer::Output::BlockId:
      return loadSurfaceProgram("terrain.vert", "terrain.frag", SurfaceOutput::ObjectId, levels + "#define OUTPUT_BLOCK_ID 1\n");
    case TerrainRenderer::Output::GBuffer: return loadSurfaceProgram("terrain.vert", "terrain.frag", SurfaceOutput::GBuffer, levels);
    case TerrainRenderer::Output::LightDepth:
      return loadSurfaceProgram("terrain.vert", "terrain.frag", SurfaceOutput::LightDepth, levels);
    case TerrainRenderer::Output::Lit: break;
  }
  return loadSurfaceProgram("terrain.vert", "terrain.frag", SurfaceOutput::Lit, levels);
}

}  // namespace

TerrainRenderer::TerrainRenderer(const terrain::Terrain& terrain, Output output, std::uint32_t objectIdBase)
    : terrain_(terrain),
      objectIdBase_(objectIdBase),
      output_(output),
      program_(loadTerrainProgram(output)),
      viewUniforms_(kViewBlockBinding, sizeof(ViewBlock)),
      terrainViewUniforms_(kTerrainViewBlockBinding, sizeof(TerrainViewBlock)) {
  const terrain::Heightfield& h = terrain.heightfield();
  setProgramConstants(program_);
  heights_ = gl::Texture(GL_R32F, h.samples(), h.samples());
  glTextureSubImage2D(heights_.id(), 0, 0, 0, h.samples(), h.samples(), GL_RED, GL_FLOAT, h.heights().data());
  glTextureParameteri(heights_.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(heights_.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  // The sample normals (Heightfield::sampleNormal, in double) as (x, z) in 16-bit snorm; y > 0 is
  // rebuilt in the shader. One fetch per sample instead of four heights: vertex shading runs on a
  // single thread on llvmpipe, and the terrain's is most of the geometry pass.
  if (output == Output::Lit || output == Output::GBuffer) {
    std::vector<std::int16_t> packed(static_cast<size_t>(h.samples()) * h.samples() * 2);
    for (int j = 0; j < h.samples(); ++j)
      for (int i = 0; i < h.samples(); ++i) {
        const glm::dvec3 n = h.sampleNormal(i, j);
        const size_t k = 2 * (static_cast<size_t>(j) * h.samples() + i);
        packed[k] = static_cast<std::int16_t>(std::lround(std::clamp(n.x, -1.0, 1.0) * 32767.0));
        packed[k + 1] = static_cast<std::int16_t>(std::lround(std::clamp(n.z, -1.0, 1.0) * 32767.0));
      }
    normals_ = gl::Texture(GL_RG16_SNORM, h.samples(), h.samples());
    glTextureSubImage2D(normals_.id(), 0, 0, 0, h.samples(), h.samples(), GL_RG, GL_SHORT, packed.data());
    glTextureParameteri(normals_.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(normals_.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  }

  std::vector<glm::ivec2> local;
  for (int j = 0; j <= kTileQuads; ++j)
    for (int i = 0; i <= kTileQuads; ++i) local.emplace_back(i, j);
  grid_ = gl::Buffer(local.size() * sizeof(glm::ivec2), local.data(), 0);
  std::vector<std::uint32_t> indices;
  for (int level = 0; level < kLevels; ++level) {
    const std::vector<std::uint32_t> levelIndices = terrain::tileGridIndices(level);
    indexOffset_[level] = static_cast<int>(indices.size());
    indexCount_[level] = static_cast<int>(levelIndices.size());
    indices.insert(indices.end(), levelIndices.begin(), levelIndices.end());
    const std::vector<std::uint32_t> blockIndices = terrain::blockGridIndices(level);
    blockIndexOffset_[level] = static_cast<int>(indices.size());
    blockIndexCount_[level] = static_cast<int>(blockIndices.size());
    indices.insert(indices.end(), blockIndices.begin(), blockIndices.end());
  }
  indices_ = gl::Buffer(indices.size() * sizeof(std::uint32_t), indices.data(), 0);
  // A segment holds every block of every tile once; only a shadow pass whose ramp blocks split into
  // more runs than that grows the ring (rare).
  const size_t mostInstances = static_cast<size_t>(terrain.tileCount()) * terrain::Terrain::kMaxBlockBoxes;
  instances_ = std::make_unique<gl::StreamRing>(mostInstances * sizeof(glm::ivec4), sizeof(glm::ivec4));
  // Room for a command per ramp block of a few hundred tiles; more grows the ring (rare).
  commands_ = std::make_unique<gl::StreamRing>(4096 * sizeof(IndirectCommand), sizeof(IndirectCommand));
  // Room for every block of every tile in every list: a draw grows them only as the ring above.
  for (int level = 0; level < kLevels; ++level)
    byLevel_[static_cast<size_t>(level)].reserve(static_cast<size_t>(terrain.tileCount() * terrain::blocksPerTile(level)));
  packed_.reserve(mostInstances);
  partBlocks_.reserve(mostInstances);

  const GLuint vao = vertexArray_.id();
  glVertexArrayVertexBuffer(vao, 0, grid_.id(), 0, sizeof(glm::ivec2));
  glVertexArrayElementBuffer(vao, indices_.id());
  glEnableVertexArrayAttrib(vao, 0);
  glVertexArrayAttribIFormat(vao, 0, 2, GL_INT, 0);
  glVertexArrayAttribBinding(vao, 0, 0);
  glVertexArrayVertexBuffer(vao, 1, instances_->id(), 0, sizeof(glm::ivec4));
  glVertexArrayBindingDivisor(vao, 1, 1);
  glEnableVertexArrayAttrib(vao, 1);
  glVertexArrayAttribIFormat(vao, 1, 4, GL_INT, 0);
  glVertexArrayAttribBinding(vao, 1, 1);
}

// What does not change with the view, set once per program.
void TerrainRenderer::setProgramConstants(const gl::Program& program) const {
  const terrain::Heightfield& h = terrain_.heightfield();
  program.set("uSpacing", static_cast<float>(h.spacing()));
  program.set("uTileQuads", kTileQuads);
  program.set("uTilesPerSide", terrain_.tilesPerSide());
  program.set("uObjectIdBase", objectIdBase_);
  program.set("uMorphSlack", static_cast<float>(terrain::TerrainLod::kMorphSlack));
  if (&program != &program_ || (output_ != Output::Lit && output_ != Output::GBuffer)) return;  // no material
  program.set("uAlbedo", glm::vec3(terrain_.settings().albedo));
  const Aabb box = terrain_.bounds();
  program.set("uHeightRange", glm::vec2(static_cast<float>(box.min.y), static_cast<float>(std::max(box.max.y - box.min.y, 1e-6))));
  if (cover_.id() != 0)
    program.set("uCoverOriginInvSize", glm::vec4(static_cast<float>(h.origin().x), static_cast<float>(h.origin().y),
                                                  static_cast<float>(1.0 / h.size()), 0.0f));
}

void TerrainRenderer::setGroundCover(std::span<const float> cover, int side) {
  if (side < 1 || cover.size() != static_cast<size_t>(side) * side)
    throw Error(fmt::format("TerrainRenderer::setGroundCover: {} values for a {}² grid", cover.size(), side));
  if (normals_.id() == 0) return;  // an output without a material
  // The material reads the cover from now on: a program that samples it (terrain.frag's
  // GROUND_COVER; without one, the ground is meadow and no fragment pays the lookup).
  const bool first = cover_.id() == 0;
  std::vector<float> clamped(cover.begin(), cover.end());
  for (float& c : clamped) c = std::isfinite(c) ? std::clamp(c, 0.0f, 1.0f) : 0.0f;  // nothing else reaches the GPU
  cover_ = gl::Texture(GL_R16F, side, side);
  glTextureSubImage2D(cover_.id(), 0, 0, 0, side, side, GL_RED, GL_FLOAT, clamped.data());
  glTextureParameteri(cover_.id(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTextureParameteri(cover_.id(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTextureParameteri(cover_.id(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(cover_.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  if (first) {
    program_ = loadTerrainProgram(output_, true);
    setProgramConstants(program_);
  }
}

std::vector<int> TerrainRenderer::tilesInFrustum(const Camera& camera) const {
  const Frustum frustum(camera);
  std::vector<int> tiles;
  for (int t = 0; t < terrain_.tileCount(); ++t)
    if (frustum.mayIntersect(terrain_.tileBox(t))) tiles.push_back(t);
  return tiles;
}

TerrainRenderer::Stats TerrainRenderer::draw(const Camera& camera, const terrain::TerrainLod& lod,
                                             const SunSettings& sun, std::span<const int> tiles) const {
  return draw(DrawView::fromCamera(camera, 0.0, sun), lod, tiles);
}

TerrainRenderer::Stats TerrainRenderer::draw(const DrawView& view, const terrain::TerrainLod& lod,
                                             std::span<const int> tiles) const {
  if (tiles.empty()) return {};
  // Tiles grouped by level, written at once as (tx, tz, level); one instanced draw per level.
  for (auto& level : byLevel_) level.clear();
  for (int t : tiles) {
    const int level = terrain_.tileLevel(t, lod);
    byLevel_[static_cast<size_t>(level)].emplace_back(t % terrain_.tilesPerSide(), t / terrain_.tilesPerSide(), level, 0);
  }
  return drawByLevel(view, lod, false, program_);
}

TerrainRenderer::Stats TerrainRenderer::drawBlocks(const DrawView& view, const terrain::TerrainLod& lod,
                                                   std::span<const terrain::TileBlock> blocks) const {
  if (blocks.empty()) return {};
  for (auto& level : byLevel_) level.clear();
  partBlocks_.clear();
  for (const terrain::TileBlock& b : blocks) {
    const int cells = terrain::cellsPerBlock(b.level), end = std::min(b.cells.end, cells);
    if (b.cells.first < 0 || b.cells.first >= end)
      throw Error(fmt::format("TerrainRenderer::drawBlocks: cells [{}, {}) of block {} of tile {} at level {}: expected a non-empty "
                              "span within [0, {})", b.cells.first, b.cells.end, b.block, b.tile, b.level, cells));
    const glm::ivec4 instance = blockInstance(b, "drawBlocks");
    if (b.cells.first == 0 && end == cells)
      byLevel_[static_cast<size_t>(b.level)].push_back(instance);
    else
      partBlocks_.push_back({instance, {b.cells.first, end}});
  }
  return drawByLevel(view, lod, true, program_);
}

glm::ivec4 TerrainRenderer::blockInstance(const terrain::TileBlock& b, const char* caller) const {
  if (b.level < 0 || b.level >= kLevels || b.block < 0 || b.block >= terrain::blocksPerTile(b.level) || b.tile < 0 ||
      b.tile >= terrain_.tileCount())
    throw Error(fmt::format("TerrainRenderer::{}: no block {} of tile {} at level {}", caller, b.block, b.tile, b.level));
  const int quads = terrain::blockQuads(b.level), perSide = kTileQuads / quads;
  const int origin = (b.block % perSide) * quads + 256 * ((b.block / perSide) * quads);  // terrain.vert's iTile.w
  return {b.tile % terrain_.tilesPerSide(), b.tile / terrain_.tilesPerSide(), b.level, origin};
}

int TerrainRenderer::levelWithSlot(int level, std::uint32_t slot, const char* caller) {
  if (slot > kMaxQuerySlot) throw Error(fmt::format("TerrainRenderer::{}: query slot {}: at most {}", caller, slot, kMaxQuerySlot));
  return level | static_cast<int>(slot << kQuerySlotShift);
}

const gl::Program& TerrainRenderer::queryProgram() const {
  if (!queryProgram_) {
    queryProgram_ = loadSurfaceProgram("terrain.vert", "terrain.frag", SurfaceOutput::QueryStamp,
                                       "#define TERRAIN_LEVELS " + std::to_string(kLevels) + "\n#define QUERY_SLOT_SHIFT " +
                                           std::to_string(kQuerySlotShift) + "\n");
    setProgramConstants(*queryProgram_);
  }
  return *queryProgram_;
}

TerrainRenderer::Stats TerrainRenderer::drawBlockQueries(const DrawView& view, const terrain::TerrainLod& lod,
                                                         std::span<const terrain::TileBlock> blocks,
                                                         std::span<const std::uint32_t> slots) const {
  if (blocks.size() != slots.size())
    throw Error(fmt::format("TerrainRenderer::drawBlockQueries: {} blocks, {} query slots", blocks.size(), slots.size()));
  if (blocks.empty()) return {};
  const gl::Program& program = queryProgram();
  // As drawBlocks(), with each block's query slot packed above its level (terrain.vert unpacks both).
  for (auto& level : byLevel_) level.clear();
  partBlocks_.clear();
  for (size_t i = 0; i < blocks.size(); ++i) {
    glm::ivec4 instance = blockInstance(blocks[i], "drawBlockQueries");
    instance.z = levelWithSlot(blocks[i].level, slots[i], "drawBlockQueries");
    byLevel_[static_cast<size_t>(blocks[i].level)].push_back(instance);
  }
  return drawByLevel(view, lod, true, program);
}

TerrainRenderer::Stats TerrainRenderer::drawQueries(const DrawView& view, const terrain::TerrainLod& lod, std::span<const int> tiles,
                                                    std::span<const std::uint32_t> slots) const {
  if (tiles.size() != slots.size())
    throw Error(fmt::format("TerrainRenderer::drawQueries: {} tiles, {} query slots", tiles.size(), slots.size()));
  if (tiles.empty()) return {};
  const gl::Program& program = queryProgram();
  // As draw(), with each tile's query slot packed above its level (terrain.vert unpacks both).
  for (auto& level : byLevel_) level.clear();
  for (size_t i = 0; i < tiles.size(); ++i) {
    const int t = tiles[i], level = terrain_.tileLevel(t, lod);
    byLevel_[static_cast<size_t>(level)].emplace_back(t % terrain_.tilesPerSide(), t / terrain_.tilesPerSide(),
                                                      levelWithSlot(level, slots[i], "drawQueries"), 0);
  }
  return drawByLevel(view, lod, false, program);
}

TerrainRenderer::Stats TerrainRenderer::drawByLevel(const DrawView& view, const terrain::TerrainLod& lod, bool blocks,
                                                    const gl::Program& program) const {
  const glm::dvec3 eye = view.origin;
  Stats stats;
  auto& byLevel = byLevel_;
  auto& packed = packed_;
  packed.clear();
  std::array<int, kLevels> first{};
  for (int level = 0; level < kLevels; ++level) {
    first[level] = static_cast<int>(packed.size());
    packed.insert(packed.end(), byLevel[level].begin(), byLevel[level].end());
  }
  const int firstPart = static_cast<int>(packed.size());
  if (blocks)
    for (const PartBlock& piece : partBlocks_) packed.push_back(piece.instance);
  const GLuint ringBefore = instances_->id();
  const gl::StreamRing::Allocation part = instances_->allocate(packed.size() * sizeof(glm::ivec4));
  std::memcpy(part.data, packed.data(), packed.size() * sizeof(glm::ivec4));
  if (instances_->id() != ringBefore) glVertexArrayVertexBuffer(vertexArray_.id(), 1, instances_->id(), 0, sizeof(glm::ivec4));
  const GLuint baseInstance = static_cast<GLuint>(part.offset / sizeof(glm::ivec4));

  // Differences to the eye in double (DESIGN §4), converted once.
  const terrain::Heightfield& h = terrain_.heightfield();
  TerrainViewBlock block{};
  block.originRelative = glm::vec4(static_cast<float>(h.origin().x - eye.x), static_cast<float>(eye.y),
                                   static_cast<float>(h.origin().y - eye.z), 0.0f);
  block.eye = glm::vec4(glm::vec3(eye), 0.0f);
  block.lodEyeRelative = glm::vec4(glm::vec3(lod.eye - eye), 0.0f);
  for (int level = 0; level < kLevels; ++level) {
    const bool last = level == kLevels - 1;  // the coarsest level never morphs
    block.morph[level] = last ? glm::vec4(1e30f, 2e30f, 0.0f, 0.0f)
                              : glm::vec4(static_cast<float>(lod.morphStart[level]), static_cast<float>(lod.morphEnd[level]), 0.0f, 0.0f);
  }
  viewUniforms_.bind(viewBlock(view));
  terrainViewUniforms_.bind(block);
  program.use();
  glBindTextureUnit(0, heights_.id());
  // Outputs without normals or cover never read units 1 and 2; valid textures stay bound there.
  glBindTextureUnit(1, normals_.id() != 0 ? normals_.id() : heights_.id());
  glBindTextureUnit(2, cover_.id() != 0 ? cover_.id() : heights_.id());
  glBindVertexArray(vertexArray_.id());
  const auto& offsets = blocks ? blockIndexOffset_ : indexOffset_;
  const auto& counts = blocks ? blockIndexCount_ : indexCount_;
  for (int level = 0; level < kLevels; ++level) {
    const int count = static_cast<int>(byLevel[level].size());
    if (count == 0) continue;
    glDrawElementsInstancedBaseInstance(
        GL_TRIANGLES, counts[level], GL_UNSIGNED_INT,
        reinterpret_cast<const void*>(static_cast<std::uintptr_t>(offsets[level]) * sizeof(std::uint32_t)), count,
        baseInstance + static_cast<GLuint>(first[level]));
    stats.tiles += count;
    stats.tilesPerLevel[level] = count;
    stats.triangles += static_cast<long long>(count) * counts[level] / 3;
  }
  // Blocks drawn in part (a ramp block's runs of cells, terrain::Terrain::cellsThatMayFaceAway):
  // one indirect command each, all in one multi-draw.
  if (blocks && !partBlocks_.empty()) {
    const gl::StreamRing::Allocation written = commands_->allocate(partBlocks_.size() * sizeof(IndirectCommand));
    auto* commands = static_cast<IndirectCommand*>(written.data);
    for (size_t p = 0; p < partBlocks_.size(); ++p) {
      const PartBlock& piece = partBlocks_[p];
      const int level = piece.instance.z, indices = 6 * (piece.cells.end - piece.cells.first);
      commands[p] = {static_cast<GLuint>(indices), 1, static_cast<GLuint>(offsets[level] + 6 * piece.cells.first), 0,
                     baseInstance + static_cast<GLuint>(firstPart) + static_cast<GLuint>(p)};
      stats.tiles += 1;
      stats.tilesPerLevel[level] += 1;
      stats.triangles += indices / 3;
    }
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, commands_->id());
    glMultiDrawElementsIndirect(GL_TRIANGLES, GL_UNSIGNED_INT, reinterpret_cast<const void*>(written.offset),
                                static_cast<GLsizei>(partBlocks_.size()), 0);
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
  }
  glBindVertexArray(0);
  return stats;
}

std::size_t TerrainRenderer::gpuBytes() const {
  return heights_.bytes() + normals_.bytes() + grid_.size() + indices_.size() + instances_->size() + commands_->size();
}

}  // namespace forest::render
