#pragma once
// GL test harness: gl_tests runs with --gl=<backend>; one context per process, created before the
// first test. Every test derives from GlTest, which fails the test on any KHR_debug error.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "forest/gl/context.hpp"
#include "forest/gl/debug.hpp"
#include "forest/gl/gl.hpp"
#include "forest/gl/objects.hpp"

namespace forest::test {

// The backend named on the command line ("egl", "osmesa", "window").
const std::string& backendUnderTest();
gl::Context& context();

class GlTest : public ::testing::Test {
 protected:
  void SetUp() override {
    context().makeCurrent();
    gl::resetDebugErrors();
  }
  void TearDown() override {
    glFinish();
    EXPECT_EQ(gl::debugErrorCount(), 0u) << "GL errors: " << joinedErrors();
  }
  static std::string joinedErrors() {
    std::string all;
    for (const auto& m : gl::debugErrorMessages()) all += m + "; ";
    return all;
  }
};

// The geometry pass's target in tests: object IDs (GL_R32UI) and reversed-Z float depth.
struct IdDepthTarget {
  gl::Texture ids, depth;
  gl::Framebuffer framebuffer;
  int width, height;
  IdDepthTarget(int w, int h) : ids(GL_R32UI, w, h), depth(GL_DEPTH_COMPONENT32F, w, h), width(w), height(h) {
    framebuffer.attach(GL_COLOR_ATTACHMENT0, ids);
    framebuffer.attach(GL_DEPTH_ATTACHMENT, depth);
  }
  // Binds, clears IDs to 0 (sky) and depth to 0 (far), sets the engine's depth test and culling.
  void bindAndClear() const {
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer.id());
    glViewport(0, 0, width, height);
    const GLuint zero[4] = {0, 0, 0, 0};
    glClearBufferuiv(GL_COLOR, 0, zero);
    glClearDepth(0.0);
    glClear(GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_GREATER);
    glEnable(GL_CULL_FACE);
    glCullFace(GL_BACK);
  }
  // Bottom row first, as OpenGL stores them.
  std::vector<std::uint32_t> readIds() const {
    std::vector<std::uint32_t> p(static_cast<size_t>(width) * height);
    glGetTextureImage(ids.id(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, static_cast<GLsizei>(p.size() * 4), p.data());
    return p;
  }
  std::vector<float> readDepth() const {
    std::vector<float> p(static_cast<size_t>(width) * height);
    glGetTextureImage(depth.id(), 0, GL_DEPTH_COMPONENT, GL_FLOAT, static_cast<GLsizei>(p.size() * 4), p.data());
    return p;
  }
};

}  // namespace forest::test
