// Pass timing: a record per pass per frame in both modes; the profiling mode's times are positive
// for real work. Timer-query values are not asserted (llvmpipe's are unreliable, DESIGN §3).
#include <set>

#include "forest/core/error.hpp"
#include "forest/core/scene.hpp"
#include "forest/gl/timing.hpp"
#include "forest/render/frame.hpp"
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

// What a frame calls, counted in-process the way apitrace would: glad's function pointers are
// swapped for counting wrappers while a block of frames runs.
struct GlCallLog {
  static inline int finishes = 0;
  static inline int blockingResultReads = 0;  // a result read of a query not reported available before
  static inline int resultReads = 0;
  static inline std::set<GLuint> available;
  static inline PFNGLFINISHPROC realFinish = nullptr;
  static inline PFNGLGETQUERYOBJECTIVPROC realGetQueryiv = nullptr;
  static inline PFNGLGETQUERYOBJECTUI64VPROC realGetQueryui64v = nullptr;

  static void GLAD_API_PTR finish() {
    ++finishes;
    realFinish();
  }
  static void GLAD_API_PTR getQueryiv(GLuint id, GLenum name, GLint* value) {
    realGetQueryiv(id, name, value);
    if (name == GL_QUERY_RESULT_AVAILABLE && *value) available.insert(id);
  }
  static void GLAD_API_PTR getQueryui64v(GLuint id, GLenum name, GLuint64* value) {
    if (name == GL_QUERY_RESULT) {
      ++resultReads;
      if (!available.count(id)) ++blockingResultReads;
      available.erase(id);  // the next use of this query must be reported available again
    }
    realGetQueryui64v(id, name, value);
  }

  GlCallLog() {
    finishes = blockingResultReads = resultReads = 0;
    available.clear();
    realFinish = glad_glFinish;
    realGetQueryiv = glad_glGetQueryObjectiv;
    realGetQueryui64v = glad_glGetQueryObjectui64v;
    glad_glFinish = &finish;
    glad_glGetQueryObjectiv = &getQueryiv;
    glad_glGetQueryObjectui64v = &getQueryui64v;
  }
  ~GlCallLog() {
    glad_glFinish = realFinish;
    glad_glGetQueryObjectiv = realGetQueryiv;
    glad_glGetQueryObjectui64v = realGetQueryui64v;
  }
};

// A box over a plane, seen from above: every pass of the frame has work.
Scene boxOnPlane() {
  Scene scene;
  scene.sun.direction = glm::normalize(glm::dvec3(0.35, -1.0, 0.25));
  scene.props.push_back({glm::dvec3(-40, -1, -40), glm::dvec3(40, 0, 40), glm::dvec3(0.6)});
  scene.props.push_back({glm::dvec3(-2, 3, -2), glm::dvec3(2, 5, 2), glm::dvec3(0.8)});
  scene.camera.position = {0, 22, 26};
  scene.camera.pitch_deg = -42.0;
  return scene;
}

// DESIGN §9: with timer queries nothing in a frame waits for the GPU — no glFinish, and every
// timestamp is read only after GL_QUERY_RESULT_AVAILABLE reported it — and every frame's six pass
// times still arrive, each frame once, under its number. In profiling mode each pass is bracketed
// by glFinish, so at least one per pass.
TEST_F(GlTest, QueryTimedFramesNeverWaitAndDeliverEveryFramesPassTimes) {
  const Scene scene = boxOnPlane();
  render::Frame frame(scene, 320, 180);
  render::FrameSettings settings;
  settings.timing = gl::TimingMode::GpuQueries;
  settings.blurRadius = 3.0;
  constexpr int kFrames = 12;
  std::vector<gl::FrameTiming> timings;
  {
    GlCallLog log;
    for (int f = 0; f < kFrames; ++f) {
      const render::FrameStats stats = frame.render(frame.startCamera(), f / 30.0, settings);
      EXPECT_EQ(stats.frameNumber, static_cast<std::uint64_t>(f));
      EXPECT_TRUE(stats.passTimesPending);
      for (gl::FrameTiming& t : frame.takePassTimes()) timings.push_back(std::move(t));
    }
    EXPECT_EQ(GlCallLog::finishes, 0) << "glFinish inside query-timed frames";
    EXPECT_EQ(GlCallLog::blockingResultReads, 0) << "of " << GlCallLog::resultReads << " timestamp reads";
  }
  for (gl::FrameTiming& t : frame.drainPassTimes()) timings.push_back(std::move(t));
  ASSERT_EQ(timings.size(), static_cast<size_t>(kFrames));
  for (size_t f = 0; f < timings.size(); ++f) {
    EXPECT_EQ(timings[f].frame, f);
    ASSERT_EQ(timings[f].passes.size(), kFramePassCount);
    for (size_t p = 0; p < timings[f].passes.size(); ++p) {
      EXPECT_EQ(timings[f].passes[p].pass, kFramePassNames.names()[p]);
      EXPECT_GE(timings[f].passes[p].ms, 0.0);
    }
  }

  settings.timing = gl::TimingMode::Profiling;
  GlCallLog log;
  const render::FrameStats profiled = frame.render(frame.startCamera(), 0.0, settings);
  EXPECT_GE(GlCallLog::finishes, static_cast<int>(kFramePassCount));
  EXPECT_FALSE(profiled.passTimesPending);
  EXPECT_EQ(profiled.frameNumber, static_cast<std::uint64_t>(kFrames));  // numbering goes on across modes
  EXPECT_GT(profiled.passMs[FramePass::Geometry] + profiled.passMs[FramePass::Shadow] + profiled.passMs[FramePass::Lighting], 0.0);
  EXPECT_TRUE(frame.takePassTimes().empty());
}

}  // namespace
}  // namespace forest::test
