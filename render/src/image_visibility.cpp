#include "image_visibility.hpp"

#include <cstdint>
#include <limits>

#include "forest/core/error.hpp"
#include "forest/terrain/terrain.hpp"

namespace forest::render {
namespace {
constexpr GLuint kRecordBinding = 7;  // shaders/lighting.frag's ImageRecord
constexpr int kBlocksPerTile = terrain::Terrain::kMaxBlockBoxes;  // the 4 × 4 blocks of levels 0–3
static_assert(kBlocksPerTile == 16, "lighting.frag's recordShown places a pixel in a tile's 4 × 4 blocks");
}  // namespace

ImageVisibility::ImageVisibility(const SceneObjects& objects)
    : objects_(objects),
      blockSlots_(objects.boxes().size() + 1),
      shownObjects_(objects.boxes().size(), 0),
      shownBlocks_(objects.tileCount(), 0) {
  record_ = gl::ReadMappedStamps(blockSlots_ + objects.tileCount() * kBlocksPerTile);
}

ImageVisibility::~ImageVisibility() { forget(); }

void ImageVisibility::beginRecord(FrameBlock& block, const Camera& camera) {
  // Nonzero (the cleared slots hold 0); after 2³² frames a stamp repeats, and a slot unwritten
  // since then reads as shown: an object drawn untested once, never a pixel lost.
  stamp_ = stamp_ == std::numeric_limits<std::uint32_t>::max() ? 1u : stamp_ + 1u;
  const terrain::Terrain* terrain = objects_.terrain();
  block.imageRecord = glm::uvec4(stamp_, terrain ? static_cast<std::uint32_t>(terrain->tilesPerSide()) : 1u,
                                 static_cast<std::uint32_t>(objects_.tileCount()), static_cast<std::uint32_t>(blockSlots_));
  if (terrain) {
    const double spacing = terrain->heightfield().spacing();
    const glm::dvec2 origin = terrain->heightfield().origin();
    block.imageTerrain = glm::vec4(static_cast<float>((camera.position.x - origin.x) / spacing),
                                   static_cast<float>((camera.position.z - origin.y) / spacing), static_cast<float>(1.0 / spacing),
                                   static_cast<float>(terrain::kTileQuads));
  }
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kRecordBinding, record_.id());
}

void ImageVisibility::endRecord() {
  if (fence_) glDeleteSync(fence_);
  // Shader writes reach a mapped buffer after this barrier and a fence (GL 4.5 §7.12.2); the
  // flush lets the fence signal before the next frame asks.
  glMemoryBarrier(GL_CLIENT_MAPPED_BUFFER_BARRIER_BIT);
  fence_ = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
  glFlush();
}

bool ImageVisibility::collect(bool wait) {
  if (!fence_) return false;
  const GLuint64 timeout = wait ? std::numeric_limits<GLuint64>::max() : 0;
  const GLenum status = glClientWaitSync(fence_, GL_SYNC_FLUSH_COMMANDS_BIT, timeout);
  if (status == GL_WAIT_FAILED) throw Error("ImageVisibility: waiting for the lighting pass failed");
  if (status == GL_TIMEOUT_EXPIRED) return false;  // async: not finished; asked again next frame
  glDeleteSync(fence_);
  fence_ = nullptr;
  for (std::size_t o = 0; o < shownObjects_.size(); ++o) shownObjects_[o] = record_[o + 1] == stamp_ ? 1 : 0;
  for (std::size_t t = 0; t < shownBlocks_.size(); ++t) {
    std::uint16_t bits = 0;
    const std::size_t tile = blockSlots_ + t * kBlocksPerTile;
    for (std::size_t b = 0; b < static_cast<std::size_t>(kBlocksPerTile); ++b)
      if (record_[tile + b] == stamp_) bits = static_cast<std::uint16_t>(bits | 1u << b);
    shownBlocks_[t] = bits;
  }
  return true;
}

void ImageVisibility::forget() {
  if (fence_) glDeleteSync(fence_);
  fence_ = nullptr;
}

}  // namespace forest::render
