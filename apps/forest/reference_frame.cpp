#include "reference_frame.hpp"

#include <chrono>
#include <string>
#include <vector>

#include "forest/core/statistics.hpp"

namespace forest::app {
namespace {
constexpr int kGrid = 256;  // cells per side: 2·256² triangles
constexpr int kFullScreenPasses = 3;
constexpr int kTaps = 16;
}  // namespace

ReferenceFrame::ReferenceFrame(int width, int height)
    : width_(width),
      height_(height),
      mesh_(gl::loadProgram({"reference_frame.vert", "reference_frame.frag"}, "#define MESH 1\n#define GRID " + std::to_string(kGrid) + "\n")),
      pass_(gl::loadProgram({"reference_frame.vert", "reference_frame.frag"}, "#define TAPS " + std::to_string(kTaps) + "\n")),
      colour_{gl::Texture(GL_RGBA8, width, height), gl::Texture(GL_RGBA8, width, height)},
      depth_(GL_DEPTH_COMPONENT32F, width, height) {
  for (int i = 0; i < 2; ++i) {
    target_[static_cast<std::size_t>(i)].attach(GL_COLOR_ATTACHMENT0, colour_[static_cast<std::size_t>(i)]);
    target_[static_cast<std::size_t>(i)].attach(GL_DEPTH_ATTACHMENT, depth_);
    target_[static_cast<std::size_t>(i)].checkComplete("reference frame");
  }
}

double ReferenceFrame::timeOnceMs() {
  glFinish();
  const auto start = std::chrono::steady_clock::now();
  glBindVertexArray(noBuffers_.id());
  glViewport(0, 0, width_, height_);
  glDisable(GL_SCISSOR_TEST);
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);
  glDepthMask(GL_TRUE);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glBindFramebuffer(GL_FRAMEBUFFER, target_[0].id());
  glClearColor(0.5f, 0.6f, 0.8f, 1.0f);
  glClearDepth(1.0);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  mesh_.use();
  glDrawArrays(GL_TRIANGLES, 0, 6 * kGrid * kGrid);
  glDisable(GL_DEPTH_TEST);
  pass_.use();
  for (int p = 0; p < kFullScreenPasses; ++p) {
    glBindTextureUnit(0, colour_[static_cast<std::size_t>(p % 2)].id());
    glBindFramebuffer(GL_FRAMEBUFFER, target_[static_cast<std::size_t>((p + 1) % 2)].id());
    glDrawArrays(GL_TRIANGLES, 0, 3);
  }
  glFinish();
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  // The engine's state (reversed-Z), for the passes that rely on it between their own settings.
  glBindTextureUnit(0, 0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glBindVertexArray(0);
  glUseProgram(0);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_GREATER);
  glClearDepth(0.0);
  glEnable(GL_CULL_FACE);
  return ms;
}

double measureReferenceFrameMs(int width, int height, int repeats) {
  ReferenceFrame reference(width, height);
  std::vector<double> times;
  for (int r = 0; r < repeats + 2; ++r) {
    const double ms = reference.timeOnceMs();
    if (r >= 2) times.push_back(ms);
  }
  return percentile(times, 0.5);
}

}  // namespace forest::app
