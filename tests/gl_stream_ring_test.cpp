// The instance ring (gl/stream_ring.hpp): allocations aligned to the stride, each inside one
// segment, handed out front to back and lap after lap; what the CPU writes is what the GL holds;
// an allocation larger than a segment grows the ring.
#include <cstring>
#include <numeric>
#include <vector>

#include "forest/gl/stream_ring.hpp"
#include "gl_test_support.hpp"

namespace forest::test {
namespace {

TEST_F(GlTest, StreamRingHandsOutAlignedPartsSegmentBySegmentLapAfterLap) {
  constexpr std::size_t kStride = 48, kSegment = 1000, kSegments = 4;
  gl::StreamRing ring(kSegment, kStride, kSegments);
  const std::size_t segmentBytes = (kSegment + kStride - 1) / kStride * kStride;  // 1008: rounded up to the stride
  ASSERT_EQ(ring.size(), segmentBytes * kSegments);
  std::size_t previousEnd = 0;
  int previousSegment = 0, laps = 0;
  for (int k = 0; k < 60; ++k) {
    const std::size_t bytes = 1 + static_cast<std::size_t>(k * 37) % 400;
    const gl::StreamRing::Allocation a = ring.allocate(bytes);
    const std::size_t rounded = (bytes + kStride - 1) / kStride * kStride;
    EXPECT_EQ(a.offset % kStride, 0u) << k;
    const int segment = static_cast<int>(a.offset / segmentBytes);
    EXPECT_LE(a.offset + rounded, static_cast<std::size_t>(segment + 1) * segmentBytes) << k << ": straddles a segment";
    if (segment == previousSegment) {
      EXPECT_EQ(a.offset, previousEnd) << k << ": parts of a segment follow each other";
    } else {
      EXPECT_EQ(segment, (previousSegment + 1) % static_cast<int>(kSegments)) << k << ": segments in order";
      EXPECT_EQ(a.offset, static_cast<std::size_t>(segment) * segmentBytes) << k;
      laps += segment == 0 ? 1 : 0;
    }
    previousSegment = segment;
    previousEnd = a.offset + rounded;
    // What the CPU writes through the mapping is what the buffer holds (coherent mapping).
    std::vector<unsigned char> pattern(bytes);
    std::iota(pattern.begin(), pattern.end(), static_cast<unsigned char>(k));
    std::memcpy(a.data, pattern.data(), bytes);
    std::vector<unsigned char> held(bytes);
    glGetNamedBufferSubData(ring.id(), static_cast<GLintptr>(a.offset), static_cast<GLsizeiptr>(bytes), held.data());
    EXPECT_EQ(held, pattern) << k;
  }
  EXPECT_GE(laps, 2);  // the test went round the ring, reusing fenced segments
  EXPECT_EQ(ring.growths(), 0);

  const GLuint before = ring.id();
  const gl::StreamRing::Allocation big = ring.allocate(3 * segmentBytes);
  EXPECT_EQ(ring.growths(), 1);
  EXPECT_NE(ring.id(), before);
  EXPECT_GE(ring.size(), 3 * segmentBytes * kSegments);
  EXPECT_EQ(big.offset, 0u);
}

}  // namespace
}  // namespace forest::test
