#include "forest/gl/uniform_stream.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstring>

#include "forest/core/error.hpp"

namespace forest::gl {

UniformStream::UniformStream(GLuint binding, std::size_t blockBytes, int blocksPerSegment)
    : binding_(binding), blockBytes_(blockBytes), last_(blockBytes) {
  if (blockBytes == 0 || blocksPerSegment < 1) throw Error("gl::UniformStream: expected a block of at least 1 byte");
  GLint offsetAlignment = 256;
  glGetIntegerv(GL_UNIFORM_BUFFER_OFFSET_ALIGNMENT, &offsetAlignment);
  const std::size_t unit = static_cast<std::size_t>(std::max(offsetAlignment, 1));
  const std::size_t stride = (blockBytes + unit - 1) / unit * unit;  // every block starts aligned
  ring_ = std::make_unique<StreamRing>(stride * static_cast<std::size_t>(blocksPerSegment), stride);
}

void UniformStream::bindBytes(const void* block, std::size_t bytes) {
  if (bytes != blockBytes_)
    throw Error(fmt::format("gl::UniformStream: a block of {} bytes, built for {}", bytes, blockBytes_));
  if (!written_ || std::memcmp(last_.data(), block, bytes) != 0) {
    const StreamRing::Allocation part = ring_->allocate(bytes);
    std::memcpy(part.data, block, bytes);
    std::memcpy(last_.data(), block, bytes);
    lastOffset_ = part.offset;
    written_ = true;
    ++writes_;
  }
  glBindBufferRange(GL_UNIFORM_BUFFER, binding_, ring_->id(), static_cast<GLintptr>(lastOffset_),
                    static_cast<GLsizeiptr>(blockBytes_));
}

}  // namespace forest::gl
