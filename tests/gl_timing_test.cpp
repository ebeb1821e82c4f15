// Pass timing: a record per pass per frame in both modes; the profiling mode's times are positive
// for real work. Timer-query values are not asserted (llvmpipe's are unreliable, DESIGN §3).
#include "forest/core/error.hpp"
#include "forest/gl/timing.hpp"
#include "forest/render/offscreen_target.hpp"
#include "gl_test_support.hpp"

namespace forest::test {
namespace {

// Real work for llvmpipe: clears of a 1024² target.
void busyWork(render::OffscreenTarget& target) {
  target.bind();
  for (int i = 0; i < 20; ++i) {
    glClearColor(static_cast<float>(i) / 20.0f, 0.0f, 0.0f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  }
}

std::vector<gl::FrameTiming> runFrames(gl::PassTimer& timer, render::OffscreenTarget& target, int frames) {
  for (int f = 0; f < frames; ++f) {
    timer.beginFrame();
    {
      auto pass = timer.scope("geometry");
      busyWork(target);
    }
    {
      auto pass = timer.scope("shadow");
      busyWork(target);
    }
    timer.endFrame();
  }
  return timer.drain();
}

TEST_F(GlTest, ProfilingModeTimesEachPassPositive) {
  render::OffscreenTarget target(1024, 1024);
  gl::PassTimer timer(gl::TimingMode::Profiling);
  const auto frames = runFrames(timer, target, 3);
  ASSERT_EQ(frames.size(), 3u);
  for (size_t f = 0; f < frames.size(); ++f) {
    EXPECT_EQ(frames[f].frame, f);
    ASSERT_EQ(frames[f].passes.size(), 2u);
    EXPECT_EQ(frames[f].passes[0].pass, "geometry");
    EXPECT_EQ(frames[f].passes[1].pass, "shadow");
    double sum = 0;
    for (const auto& p : frames[f].passes) {
      EXPECT_GT(p.ms, 0.0) << p.pass;
      sum += p.ms;
    }
    EXPECT_LE(sum, frames[f].cpuFrameMs);
  }
}

TEST_F(GlTest, GpuQueryModeDeliversARecordPerPassLate) {
  render::OffscreenTarget target(256, 256);
  gl::PassTimer timer(gl::TimingMode::GpuQueries, 2);
  const auto frames = runFrames(timer, target, 5);
  ASSERT_EQ(frames.size(), 5u);
  for (const auto& f : frames) {
    ASSERT_EQ(f.passes.size(), 2u);
    EXPECT_GE(f.passes[0].ms, 0.0);
  }
}

TEST_F(GlTest, UnbalancedPassIsAnError) {
  gl::PassTimer timer(gl::TimingMode::Profiling);
  timer.beginFrame();
  timer.begin("open");
  EXPECT_THROW(timer.endFrame(), Error);
  timer.end();
  timer.endFrame();
  EXPECT_THROW(timer.end(), Error);
}

}  // namespace
}  // namespace forest::test
