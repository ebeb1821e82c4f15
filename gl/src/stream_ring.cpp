#include "forest/gl/stream_ring.hpp"

#include <fmt/format.h>

#include "forest/core/error.hpp"

namespace forest::gl {
namespace {

constexpr GLbitfield kMapping = GL_MAP_WRITE_BIT | GL_MAP_PERSISTENT_BIT | GL_MAP_COHERENT_BIT;

std::size_t roundUp(std::size_t bytes, std::size_t alignment) { return (bytes + alignment - 1) / alignment * alignment; }

}  // namespace

StreamRing::StreamRing(std::size_t segmentBytes, std::size_t alignment, int segments)
    : alignment_(alignment), segmentCount_(segments) {
  if (alignment == 0 || segments < 2) throw Error("gl::StreamRing: expected an alignment > 0 and at least 2 segments");
  create(segmentBytes);
}

StreamRing::~StreamRing() { release(); }

void StreamRing::release() {
  for (GLsync& fence : fences_)
    if (fence != nullptr) glDeleteSync(fence);
  fences_.clear();
  if (mapped_ != nullptr) glUnmapNamedBuffer(buffer_.id());
  mapped_ = nullptr;
  buffer_ = Buffer();
}

void StreamRing::create(std::size_t segmentBytes) {
  release();
  segmentBytes_ = roundUp(std::max<std::size_t>(segmentBytes, alignment_), alignment_);
  const std::size_t bytes = segmentBytes_ * static_cast<std::size_t>(segmentCount_);
  buffer_ = Buffer(bytes, nullptr, kMapping);
  mapped_ = static_cast<unsigned char*>(glMapNamedBufferRange(buffer_.id(), 0, static_cast<GLsizeiptr>(bytes), kMapping));
  if (mapped_ == nullptr) throw Error(fmt::format("gl::StreamRing: could not map {} bytes persistently", bytes));
  fences_.assign(static_cast<size_t>(segmentCount_), nullptr);
  head_ = 0;
  segment_ = 0;
}

StreamRing::Allocation StreamRing::allocate(std::size_t bytes) {
  bytes = roundUp(std::max<std::size_t>(bytes, 1), alignment_);
  if (bytes > segmentBytes_) {
    // Larger than a segment: a bigger ring. The old buffer may still be read by queued draws; GL
    // keeps its storage alive until they finish, so deleting it here is safe.
    ++growths_;
    create(std::max(bytes, 2 * segmentBytes_));
  }
  const std::size_t segmentEnd = static_cast<std::size_t>(segment_ + 1) * segmentBytes_;
  if (head_ + bytes > segmentEnd) {
    // Leave this segment: fence what was issued with its data, and enter the next one (the first
    // after the last), waiting for the GPU to be done with it from the previous lap.
    fences_[static_cast<size_t>(segment_)] = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
    segment_ = (segment_ + 1) % segmentCount_;
    head_ = static_cast<std::size_t>(segment_) * segmentBytes_;
    GLsync& fence = fences_[static_cast<size_t>(segment_)];
    if (fence != nullptr) {
      if (glClientWaitSync(fence, 0, 0) == GL_TIMEOUT_EXPIRED) {
        ++waits_;
        while (glClientWaitSync(fence, GL_SYNC_FLUSH_COMMANDS_BIT, 1000000000) == GL_TIMEOUT_EXPIRED) {
        }
      }
      glDeleteSync(fence);
      fence = nullptr;
    }
  }
  const Allocation a{head_, mapped_ + head_};
  head_ += bytes;
  return a;
}

}  // namespace forest::gl
