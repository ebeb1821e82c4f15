#pragma once
// GL test harness: gl_tests runs with --gl=<backend>; one context per process, created before the
// first test. Every test derives from GlTest, which fails the test on any KHR_debug error.
#include <gtest/gtest.h>

#include <string>

#include "forest/gl/context.hpp"
#include "forest/gl/debug.hpp"
#include "forest/gl/gl.hpp"

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

}  // namespace forest::test
