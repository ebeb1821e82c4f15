// Contexts: each backend gives 4.5 core; a known triangle rasterises exactly by the pixel-centre
// rule; the image is written for the cross-backend comparison; GL errors are caught; GPU memory
// is counted.
#include <gmock/gmock.h>

#include <array>
#include <filesystem>

#include "forest/core/error.hpp"
#include "forest/core/image.hpp"
#include "forest/gl/objects.hpp"
#include "forest/gl/shader.hpp"
#include "forest/render/offscreen_target.hpp"
#include "gl_test_support.hpp"
#include "test_paths.hpp"

namespace forest::test {
namespace {

constexpr int kWidth = 64, kHeight = 48;
// Vertices in window pixels, on a 1/8-pixel grid: exact in float and on llvmpipe's 1/256 snap grid.
constexpr std::array<std::array<double, 2>, 3> kTriangle = {{{5.25, 3.5}, {58.75, 10.125}, {20.5, 44.875}}};

const char* kVertex = R"(#version 450 core
layout(location = 0) in vec2 aPosition;
void main() { gl_Position = vec4(aPosition, 0.5, 1.0); })";
const char* kFragment = R"(#version 450 core
out vec4 color;
void main() { color = vec4(1.0, 0.0, 0.0, 1.0); })";

// Twice the signed area of (a, b, p): > 0 when p is left of a→b.
double edge(const std::array<double, 2>& a, const std::array<double, 2>& b, double px, double py) {
  return (b[0] - a[0]) * (py - a[1]) - (b[1] - a[1]) * (px - a[0]);
}

TEST_F(GlTest, BackendGivesCore45) {
  const gl::ContextInfo& info = context().info();
  EXPECT_EQ(gl::kBackendNames.name(info.backend), backendUnderTest());
  EXPECT_GE(info.major * 10 + info.minor, 45);
  EXPECT_TRUE(info.coreProfile);
  EXPECT_FALSE(info.renderer.empty());
}

TEST_F(GlTest, KnownTriangleFollowsThePixelCentreRule) {
  render::OffscreenTarget target(kWidth, kHeight);
  target.bind();
  glClearColor(0, 0, 0, 1);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);

  std::array<float, 6> ndc{};
  for (size_t v = 0; v < 3; ++v) {
    ndc[2 * v] = static_cast<float>(2.0 * kTriangle[v][0] / kWidth - 1.0);
    ndc[2 * v + 1] = static_cast<float>(2.0 * kTriangle[v][1] / kHeight - 1.0);
  }
  gl::Buffer vertices(sizeof(ndc), ndc.data(), 0);
  gl::VertexArray vao;
  glVertexArrayVertexBuffer(vao.id(), 0, vertices.id(), 0, 2 * sizeof(float));
  glEnableVertexArrayAttrib(vao.id(), 0);
  glVertexArrayAttribFormat(vao.id(), 0, 2, GL_FLOAT, GL_FALSE, 0);
  glVertexArrayAttribBinding(vao.id(), 0, 0);
  gl::Program program = gl::compileProgram({{GL_VERTEX_SHADER, "triangle.vert", kVertex},
                                            {GL_FRAGMENT_SHADER, "triangle.frag", kFragment}});
  program.use();
  glBindVertexArray(vao.id());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);

  Image8 image = target.readColor();  // top row first
  int covered = 0, mismatches = 0;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const double cx = x + 0.5, cy = y + 0.5;  // GL window coordinates, y up
      const double e0 = edge(kTriangle[0], kTriangle[1], cx, cy);
      const double e1 = edge(kTriangle[1], kTriangle[2], cx, cy);
      const double e2 = edge(kTriangle[2], kTriangle[0], cx, cy);
      ASSERT_TRUE(e0 != 0 && e1 != 0 && e2 != 0) << "test triangle must not pass through a pixel centre";
      const bool inside = e0 > 0 && e1 > 0 && e2 > 0;
      const int row = kHeight - 1 - y;
      const bool red = image.at(x, row, 0) == 255 && image.at(x, row, 1) == 0;
      covered += inside;
      if (inside != red) ++mismatches;
    }
  }
  EXPECT_GT(covered, 800);  // area ≈ 1019 px²
  EXPECT_EQ(mismatches, 0);
  writeImage(std::filesystem::path(FOREST_TEST_OUTPUT) / ("triangle-" + backendUnderTest() + ".png"), image);
}

TEST_F(GlTest, DebugOutputReportsGlErrors) {
  glBindBuffer(GL_ARRAY_BUFFER, 987654);  // not a buffer name: GL_INVALID_OPERATION
  glFinish();
  EXPECT_GE(gl::debugErrorCount(), 1u);
  EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_INVALID_OPERATION));
  gl::resetDebugErrors();
}

TEST_F(GlTest, GpuMemoryIsCountedByTheWrappers) {
  const std::int64_t before = gl::gpuMemory().bytes;
  {
    gl::Texture texture(GL_RGBA8, 256, 128);
    gl::Buffer buffer(1000, nullptr);
    EXPECT_EQ(gl::gpuMemory().bytes - before, 256 * 128 * 4 + 1000);
    gl::Texture moved = std::move(texture);
    EXPECT_EQ(gl::gpuMemory().bytes - before, 256 * 128 * 4 + 1000);
    gl::Texture mipmapped(GL_R32F, 64, 64, 7);
    EXPECT_EQ(mipmapped.bytes(), 4u * (4096 + 1024 + 256 + 64 + 16 + 4 + 1));
  }
  EXPECT_EQ(gl::gpuMemory().bytes, before);
  EXPECT_GE(gl::gpuMemory().peakBytes, before + 256 * 128 * 4 + 1000);
}

TEST_F(GlTest, AbsurdTextureSizeIsRefusedBeforeAllocating) {
  EXPECT_THROW(gl::Texture(GL_RGBA8, 65536 * 4, 65536 * 4), Error);
}

}  // namespace
}  // namespace forest::test
