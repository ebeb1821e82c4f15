#pragma once
// Per-draw data (instances) written once, where the GPU reads it (DESIGN §9): a persistently and
// coherently mapped buffer filled front to back in laps. Draws address their part by base
// instance, so nothing the GPU may still read is ever rewritten and no glBufferSubData call is
// made. The ring is cut into segments; an allocation never straddles two. Leaving a segment fences
// it (glFenceSync); entering a segment of the previous lap waits for its fence — which blocks only
// when the GPU is a whole ring behind. An allocation larger than a segment grows the ring (a new
// buffer, rare: the callers size it for their largest draw).
#include <cstddef>
#include <vector>

#include "forest/gl/objects.hpp"

namespace forest::gl {

class StreamRing {
 public:
  // `segmentBytes` per segment, `segments` of them; offsets are multiples of `alignment` (the
  // instance stride, so offset / stride is the base instance).
  StreamRing(std::size_t segmentBytes, std::size_t alignment, int segments = 4);
  ~StreamRing();
  StreamRing(StreamRing&&) = delete;  // owns fences and a mapping; renderers hold it in place

  struct Allocation {
    std::size_t offset = 0;  // bytes from the buffer's start, a multiple of the alignment
    void* data = nullptr;    // where to write them (coherent: no flush needed)
  };
  Allocation allocate(std::size_t bytes);
  GLuint id() const { return buffer_.id(); }
  std::size_t size() const { return buffer_.size(); }
  // Times allocate had to wait for the GPU, and had to grow the ring (tests, statistics).
  int waits() const { return waits_; }
  int growths() const { return growths_; }

 private:
  void create(std::size_t segmentBytes);
  void release();

  std::size_t alignment_;
  int segmentCount_;
  std::size_t segmentBytes_ = 0;
  Buffer buffer_;
  unsigned char* mapped_ = nullptr;
  std::size_t head_ = 0;  // next free byte
  int segment_ = 0;       // the segment head_ is in
  std::vector<GLsync> fences_;  // per segment: set when the ring left it, waited on before reuse
  int waits_ = 0, growths_ = 0;
};

}  // namespace forest::gl
