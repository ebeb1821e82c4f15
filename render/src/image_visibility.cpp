#include "image_visibility.hpp"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <limits>

#include "forest/core/error.hpp"
#include "forest/terrain/terrain.hpp"

namespace forest::render {

void ImageVisibility::shownAsVisibleSet(std::span<const Aabb> objectBoxes, const Camera& camera, const culling::CullingStats& stats,
                                        culling::CullingResult& out) const {
  out.stats = stats;
  out.visibleObjects.clear();
  for (std::size_t o = 0; o < shownObjects_.size(); ++o)
    if (shownObjects_[o] != 0) out.visibleObjects.push_back(static_cast<std::uint32_t>(o));
  out.farDepth = culling::farDepthOf(out.visibleObjects, objectBoxes, camera);
}
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
  haveSamples_ = false;  // this record has no samples
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

void ImageVisibility::recordFromPixels(const ReceiverPixels& pixels, WorkerThreads& workers, bool keepSamples) {
  forget();
  fromPixels_ = true;
  // Rows dealt in turn to the workers' bands, each marking its own flags (band 0: the record's),
  // then merged.
  const int bands = workers.count();
  const std::size_t objectCount = shownObjects_.size(), tiles = shownBlocks_.size();
  bandObjects_.resize(static_cast<std::size_t>(bands));
  bandBlocks_.resize(static_cast<std::size_t>(bands));
  constexpr int stride = culling::ReprojectedImage::kSampleStride;
  if (keepSamples) {  // the rays of the sampled pixels; their depths and objects by the bands' rows
    const shadows::EyeRays& rays = pixels.rays();
    samples_.eye = rays.eye;
    samples_.forward = rays.forward;
    samples_.up = rays.up;
    samples_.right = rays.right;
    samples_.columns.clear();
    samples_.rows.clear();
    for (int x = 0; x < pixels.width(); x += stride) samples_.columns.push_back(pixels.columns()[static_cast<std::size_t>(x)]);
    for (int y = 0; y < pixels.height(); y += stride) samples_.rows.push_back(pixels.row(y));
    samples_.depths.resize(samples_.columns.size() * samples_.rows.size());
    samples_.objects.resize(samples_.depths.size());
  }
  workers.run([&](int band) {
    std::vector<std::uint8_t>& objects = band == 0 ? shownObjects_ : bandObjects_[static_cast<std::size_t>(band)];
    std::vector<std::uint16_t>& blocks = band == 0 ? shownBlocks_ : bandBlocks_[static_cast<std::size_t>(band)];
    objects.assign(objectCount, 0);
    blocks.assign(tiles, 0);
    for (int y = band; y < pixels.height(); y += bands) {
      markRow(pixels, y, objects, blocks);
      if (keepSamples && y % stride == 0) sampleRow(pixels, y);
    }
  });
  haveSamples_ = keepSamples;
  for (std::size_t band = 1; band < static_cast<std::size_t>(bands); ++band) {
    for (std::size_t o = 0; o < shownObjects_.size(); ++o) shownObjects_[o] |= bandObjects_[band][o];
    for (std::size_t t = 0; t < shownBlocks_.size(); ++t) shownBlocks_[t] = static_cast<std::uint16_t>(shownBlocks_[t] | bandBlocks_[band][t]);
  }
}

void ImageVisibility::markRow(const ReceiverPixels& pixels, int y, std::vector<std::uint8_t>& objects,
                              std::vector<std::uint16_t>& blocks) const {
  const std::size_t objectCount = objects.size(), tiles = blocks.size();
  const terrain::Terrain* terrain = objects_.terrain();
  // A terrain pixel's block, as lighting.frag's recordShown places it: its position (the eye plus
  // its eye depth times its ray at depth 1) in heightfield samples, within its tile's quads, in
  // the tile's 4 × 4 blocks.
  const double spacing = terrain ? terrain->heightfield().spacing() : 1.0;
  const glm::dvec2 origin = terrain ? terrain->heightfield().origin() : glm::dvec2(0.0);
  const std::size_t tilesPerSide = terrain ? static_cast<std::size_t>(terrain->tilesPerSide()) : 1;
  constexpr int quads = terrain::kTileQuads, blockQuads = quads / 4;
  const shadows::EyeRays& rays = pixels.rays();
  const glm::dvec2 eye = (glm::dvec2(rays.eye.x, rays.eye.z) - origin) / spacing;
  const glm::dvec3 rowRay = rays.forward + static_cast<double>(pixels.row(y)) * rays.up;
  const glm::dvec2 rowXz = glm::dvec2(rowRay.x, rowRay.z) / spacing, rightXz = glm::dvec2(rays.right.x, rays.right.z) / spacing;
  const std::span<const float> columns = pixels.columns();
  std::uint32_t last = 0;
  std::size_t lastTile = tiles;
  glm::dvec2 tileFirst(0.0);  // the last tile's first sample
  for (int x = 0; x < pixels.width(); ++x) {
    const glm::uvec4& surface = pixels.surface(x, y);
    const std::uint32_t id = surface.w;  // object o + 1; 0: the sky
    if (id == last || id == 0 || id > objectCount) continue;  // a tree or prop repeats over its pixels
    const std::size_t object = id - 1;
    objects[object] = 1;
    if (object >= tiles) {
      last = id;
      continue;
    }
    if (object != lastTile) {
      lastTile = object;
      tileFirst = glm::dvec2(static_cast<double>(object % tilesPerSide), static_cast<double>(object / tilesPerSide)) * static_cast<double>(quads);
    }
    const double z = std::bit_cast<float>(surface.x);
    const glm::dvec2 samples = eye + z * (rowXz + static_cast<double>(columns[static_cast<std::size_t>(x)]) * rightXz) - tileFirst;
    // The quad (floor of the sample position) clamped into the tile: clamping first, the
    // truncation of a non-negative value is its floor.
    const int ix = static_cast<int>(std::clamp(samples.x, 0.0, quads - 1.0)), iz = static_cast<int>(std::clamp(samples.y, 0.0, quads - 1.0));
    blocks[object] = static_cast<std::uint16_t>(blocks[object] | 1u << (iz / blockQuads * 4 + ix / blockQuads));
  }
}

void ImageVisibility::sampleRow(const ReceiverPixels& pixels, int y) {
  constexpr int stride = culling::ReprojectedImage::kSampleStride;
  const std::size_t first = static_cast<std::size_t>(y / stride) * samples_.columns.size();
  for (int x = 0, i = 0; x < pixels.width(); x += stride, ++i) {
    const glm::uvec4& surface = pixels.surface(x, y);  // x: eye depth bits (0 for the sky), w: object + 1 (0: the sky)
    samples_.depths[first + static_cast<std::size_t>(i)] = std::bit_cast<float>(surface.x);
    samples_.objects[first + static_cast<std::size_t>(i)] = surface.w;
  }
}

int ImageVisibility::hideByReprojection(const Camera& next) {
  if (!haveSamples_) return 0;
  haveSamples_ = false;  // one guess per record
  // One cell per sample where nothing moved. Candidates: the trees and props that showed (a
  // tile's blocks have their own record, shownBlocks).
  reprojected_.begin(next, static_cast<int>(samples_.columns.size()), static_cast<int>(samples_.rows.size()), shownObjects_,
                     objects_.tileCount());
  // On this thread: at the start of a frame the renderer's threads are still drawing the last one
  // (measured with the first, per-point splat: two bands on the frame's workers took 1.06 ms
  // where this thread took 0.80).
  reprojected_.splat(samples_);
  return reprojected_.clearHidden(shownObjects_);
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
  if (fromPixels_) {
    fromPixels_ = false;
    return true;
  }
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
  fromPixels_ = false;
  haveSamples_ = false;
}

}  // namespace forest::render
