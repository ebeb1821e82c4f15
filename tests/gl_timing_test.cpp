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

// One frame of two passes, "geometry" and "shadow".
void runFrame(gl::PassTimer& timer, render::OffscreenTarget& target) {
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

std::vector<gl::FrameTiming> runFrames(gl::PassTimer& timer, render::OffscreenTarget& target, int frames) {
  for (int f = 0; f < frames; ++f) runFrame(timer, target);
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

// Timer queries are read `latency` frames late and never later: after frame f ends, frames
// 0 … f − latency have been delivered (takeCompleted), in order, each once, with a record per pass.
TEST_F(GlTest, GpuQueryModeDeliversEveryFrameAtMostLatencyFramesLate) {
  render::OffscreenTarget target(256, 256);
  constexpr int kLatency = 2, kFrames = 6;
  gl::PassTimer timer(gl::TimingMode::GpuQueries, kLatency);
  std::vector<gl::FrameTiming> got;
  for (int f = 0; f < kFrames; ++f) {
    runFrame(timer, target);
    for (gl::FrameTiming& t : timer.takeCompleted()) got.push_back(std::move(t));
    EXPECT_GE(static_cast<int>(got.size()), f + 1 - kLatency) << "after frame " << f;
    EXPECT_LE(static_cast<int>(got.size()), f + 1) << "after frame " << f;
  }
  for (gl::FrameTiming& t : timer.drain()) got.push_back(std::move(t));
  ASSERT_EQ(got.size(), static_cast<size_t>(kFrames));
  for (size_t f = 0; f < got.size(); ++f) {
    EXPECT_EQ(got[f].frame, f);
    ASSERT_EQ(got[f].passes.size(), 2u);
    EXPECT_EQ(got[f].passes[0].pass, "geometry");
    EXPECT_EQ(got[f].passes[1].pass, "shadow");
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
