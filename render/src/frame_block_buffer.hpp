#pragma once
// The frame block (uniform_blocks.hpp) in a buffer the full-screen passes read.
#include "forest/gl/uniform_stream.hpp"
#include "forest/render/uniform_blocks.hpp"

namespace forest::render {

// The frame block as the full-screen passes take it, as an argument: written once per frame into
// a mapped ring (gl::UniformStream), and bound by each pass that reads it (binding it again
// writes nothing).
class FrameBlockBuffer {
 public:
  FrameBlockBuffer() : stream_(kFrameBlockBinding, sizeof(FrameBlock)) {}
  // This frame's block, written once.
  void write(const FrameBlock& block) {
    block_ = block;
    stream_.bind(block_);
  }
  // Makes it the block the passes' programs read (the same bytes: nothing is written again).
  void bind() const { stream_.bind(block_); }

 private:
  mutable gl::UniformStream stream_;
  FrameBlock block_{};
};

}  // namespace forest::render
