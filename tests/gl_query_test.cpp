// Occlusion queries are exact: boxes behind, in front of and straddling a depth-filled quad.
// Orthographic (positions given in NDC, depth = z with the zero-to-one clip convention, reversed-Z:
// larger depth is nearer, test GL_GREATER), so each box covers an exact pixel rectangle.
#include <array>

#include "forest/gl/objects.hpp"
#include "forest/gl/shader.hpp"
#include "forest/render/offscreen_target.hpp"
#include "gl_test_support.hpp"

namespace forest::test {
namespace {

constexpr int kSize = 64;

const char* kVertex = R"(#version 450 core
layout(location = 0) in vec3 aPosition;
void main() { gl_Position = vec4(aPosition, 1.0); })";
const char* kFragment = R"(#version 450 core
out vec4 color;
void main() { color = vec4(1.0); })";

double ndc(int pixel) { return 2.0 * pixel / kSize - 1.0; }

// 12 triangles of the box [x0, x1) × [y0, y1) pixels × [z0, z1] depth.
std::vector<float> boxTriangles(int x0, int x1, int y0, int y1, double z0, double z1) {
  const double xs[2] = {ndc(x0), ndc(x1)}, ys[2] = {ndc(y0), ndc(y1)}, zs[2] = {z0, z1};
  auto corner = [&](int i) { return std::array<double, 3>{xs[i & 1], ys[(i >> 1) & 1], zs[(i >> 2) & 1]}; };
  const int faces[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1}, {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
  std::vector<float> out;
  for (const auto& f : faces) {
    for (int k : {0, 1, 2, 0, 2, 3}) {
      for (double c : corner(f[k])) out.push_back(static_cast<float>(c));
    }
  }
  return out;
}

class OcclusionQueryTest : public GlTest {
 protected:
  void SetUp() override {
    GlTest::SetUp();
    target_ = std::make_unique<render::OffscreenTarget>(kSize, kSize);
    program_ = gl::compileProgram({{GL_VERTEX_SHADER, "box.vert", kVertex}, {GL_FRAGMENT_SHADER, "box.frag", kFragment}});
    target_->bind();
    glClearDepth(0.0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_GREATER);
    glDisable(GL_CULL_FACE);
    // The occluder: a full-screen quad at depth 0.5.
    draw(boxTriangles(0, kSize, 0, kSize, 0.5, 0.5));
    // Query state: depth test on, depth and colour writes off.
    glDepthMask(GL_FALSE);
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
  }
  void TearDown() override {
    glDepthMask(GL_TRUE);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    GlTest::TearDown();
  }

  void draw(const std::vector<float>& triangles) {
    gl::Buffer buffer(triangles.size() * sizeof(float), triangles.data(), 0);
    gl::VertexArray vao;
    glVertexArrayVertexBuffer(vao.id(), 0, buffer.id(), 0, 3 * sizeof(float));
    glEnableVertexArrayAttrib(vao.id(), 0);
    glVertexArrayAttribFormat(vao.id(), 0, 3, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(vao.id(), 0, 0);
    program_.use();
    glBindVertexArray(vao.id());
    glDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(triangles.size() / 3));
    glBindVertexArray(0);
  }

  GLuint64 query(GLenum target, const std::vector<float>& triangles) {
    gl::Query q(target);
    glBeginQuery(target, q.id());
    draw(triangles);
    glEndQuery(target);
    GLuint64 result = 0;
    glGetQueryObjectui64v(q.id(), GL_QUERY_RESULT, &result);
    return result;
  }

  std::unique_ptr<render::OffscreenTarget> target_;
  gl::Program program_;
};

TEST_F(OcclusionQueryTest, BoxBehindTheQuadPassesNoSample) {
  const auto box = boxTriangles(8, 24, 8, 40, 0.1, 0.3);
  EXPECT_EQ(query(GL_SAMPLES_PASSED, box), 0u);
  EXPECT_EQ(query(GL_ANY_SAMPLES_PASSED, box), 0u);
}

TEST_F(OcclusionQueryTest, BoxInFrontCountsNearAndFarFaceExactly) {
  // 16 × 32 pixels; the near (0.9) and far (0.7) faces both pass; side faces are edge-on.
  const auto box = boxTriangles(8, 24, 8, 40, 0.7, 0.9);
  EXPECT_EQ(query(GL_SAMPLES_PASSED, box), 2u * 16u * 32u);
  EXPECT_EQ(query(GL_ANY_SAMPLES_PASSED, box), 1u);
}

TEST_F(OcclusionQueryTest, BoxStraddlingTheQuadCountsItsNearFaceOnly) {
  const auto box = boxTriangles(30, 61, 3, 10, 0.3, 0.7);
  EXPECT_EQ(query(GL_SAMPLES_PASSED, box), 31u * 7u);
  EXPECT_EQ(query(GL_ANY_SAMPLES_PASSED, box), 1u);
}

TEST_F(OcclusionQueryTest, OneVisiblePixelIsSeen) {
  const auto box = boxTriangles(63, 64, 63, 64, 0.51, 0.51);
  EXPECT_EQ(query(GL_SAMPLES_PASSED, box), 2u);  // the degenerate box's two coincident faces
  EXPECT_EQ(query(GL_ANY_SAMPLES_PASSED, box), 1u);
}

}  // namespace
}  // namespace forest::test
