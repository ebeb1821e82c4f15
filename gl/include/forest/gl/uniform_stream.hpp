#pragma once
// A uniform block written where the GPU reads it (DESIGN §9): each new value of the block goes once
// into a StreamRing (persistently mapped, fenced) and is bound by range to its binding point
// (glBindBufferRange); binding the value last written again writes nothing. Per-frame and per-pass
// values (the view, the sun, the shadow lookup) thus cost one small write each, and no
// glProgramUniform or glBufferSubData call is made per draw.
#include <cstddef>
#include <memory>
#include <type_traits>
#include <vector>

#include "forest/gl/stream_ring.hpp"

namespace forest::gl {

class UniformStream {
 public:
  // `binding`: the block's binding point (layout(std140, binding = N) in the shaders).
  UniformStream(GLuint binding, std::size_t blockBytes, int blocksPerSegment = 64);

  // Makes `block` (std140 layout, blockBytes) the value at the binding point.
  template <class Block>
  void bind(const Block& block) {
    static_assert(std::is_trivially_copyable_v<Block>);
    bindBytes(&block, sizeof(Block));
  }
  void bindBytes(const void* block, std::size_t bytes);
  // Values written so far (tests: a repeated value is not written again).
  int writes() const { return writes_; }

 private:
  GLuint binding_;
  std::size_t blockBytes_;
  std::unique_ptr<StreamRing> ring_;
  std::vector<unsigned char> last_;  // the value last written, compared byte for byte
  std::size_t lastOffset_ = 0;
  bool written_ = false;
  int writes_ = 0;
};

}  // namespace forest::gl
