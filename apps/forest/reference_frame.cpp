#include "reference_frame.hpp"

#include <algorithm>
#include <chrono>
#include <vector>

#include "forest/core/statistics.hpp"
#include "forest/gl/objects.hpp"
#include "forest/gl/shader.hpp"

namespace forest::app {
namespace {
constexpr int kGrid = 256;         // cells per side: 2·256² triangles
constexpr int kFullScreenPasses = 3;
constexpr int kTaps = 16;
}  // namespace

double measureReferenceFrameMs(int width, int height, int repeats) {
  const gl::Program mesh = gl::loadProgram({"reference_frame.vert", "reference_frame.frag"}, "#define MESH 1\n#define GRID " +
                                                                                                 std::to_string(kGrid) + "\n");
  const gl::Program pass = gl::loadProgram({"reference_frame.vert", "reference_frame.frag"}, "#define TAPS " + std::to_string(kTaps) + "\n");
  gl::Texture colour[2] = {gl::Texture(GL_RGBA8, width, height), gl::Texture(GL_RGBA8, width, height)};
  const gl::Texture depth(GL_DEPTH_COMPONENT32F, width, height);
  gl::Framebuffer target[2];
  for (int i = 0; i < 2; ++i) {
    target[i].attach(GL_COLOR_ATTACHMENT0, colour[i]);
    target[i].attach(GL_DEPTH_ATTACHMENT, depth);
    target[i].checkComplete("reference frame");
  }
  const gl::VertexArray noBuffers;
  glBindVertexArray(noBuffers.id());
  glViewport(0, 0, width, height);
  std::vector<double> times;
  for (int r = 0; r < repeats + 2; ++r) {
    glFinish();
    const auto start = std::chrono::steady_clock::now();
    glBindFramebuffer(GL_FRAMEBUFFER, target[0].id());
    glClearColor(0.5f, 0.6f, 0.8f, 1.0f);
    glClearDepth(1.0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    mesh.use();
    glDrawArrays(GL_TRIANGLES, 0, 6 * kGrid * kGrid);
    glDisable(GL_DEPTH_TEST);
    pass.use();
    for (int p = 0; p < kFullScreenPasses; ++p) {
      glBindTextureUnit(0, colour[p % 2].id());
      glBindFramebuffer(GL_FRAMEBUFFER, target[(p + 1) % 2].id());
      glDrawArrays(GL_TRIANGLES, 0, 3);
    }
    glFinish();
    if (r >= 2) times.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
  }
  glBindTextureUnit(0, 0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glBindVertexArray(0);
  return percentile(times, 0.5);
}

}  // namespace forest::app
