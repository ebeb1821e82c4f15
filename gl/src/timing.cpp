#include "forest/gl/timing.hpp"

#include "forest/core/error.hpp"

namespace forest::gl {
namespace {
using Clock = std::chrono::steady_clock;
double millisecondsBetween(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}
}  // namespace

PassTimer::PassTimer(TimingMode mode, int latency, std::uint64_t firstFrame)
    : mode_(mode), latency_(std::max(1, latency)), frameNumber_(firstFrame) {}

Query PassTimer::takeQuery() {
  if (spareQueries_.empty()) return Query(GL_TIMESTAMP);
  Query q = std::move(spareQueries_.back());
  spareQueries_.pop_back();
  return q;
}

void PassTimer::beginFrame() {
  current_ = PendingFrame{};
  current_.timing.frame = frameNumber_++;
  open_.clear();
  if (mode_ == TimingMode::Profiling) glFinish();
  frameStart_ = Clock::now();
}

void PassTimer::begin(const std::string& pass) {
  current_.timing.passes.push_back({pass, 0.0});
  const size_t index = current_.timing.passes.size() - 1;
  // Profiling: the GPU is idle here (beginFrame or the previous pass's end finished it), so the
  // clock alone starts the pass.
  if (mode_ == TimingMode::GpuQueries) {
    current_.queries.emplace_back(takeQuery(), takeQuery());
    glQueryCounter(current_.queries.back().first.id(), GL_TIMESTAMP);
  }
  open_.push_back({pass, index, Clock::now()});
}

void PassTimer::end() {
  if (open_.empty()) throw Error("PassTimer::end without begin");
  const OpenPass pass = open_.back();
  open_.pop_back();
  if (mode_ == TimingMode::Profiling) {
    glFinish();
    current_.timing.passes[pass.recordIndex].ms = millisecondsBetween(pass.start, Clock::now());
  } else {
    glQueryCounter(current_.queries[pass.recordIndex].second.id(), GL_TIMESTAMP);
  }
}

void PassTimer::endFrame() {
  if (!open_.empty()) throw Error("PassTimer::endFrame with pass '" + open_.back().name + "' still open");
  if (mode_ == TimingMode::Profiling) glFinish();
  current_.timing.cpuFrameMs = millisecondsBetween(frameStart_, Clock::now());
  if (mode_ == TimingMode::Profiling) {
    completed_.push_back(std::move(current_.timing));
  } else {
    pending_.push_back(std::move(current_));
    collect(static_cast<int>(pending_.size()) > latency_);
  }
  current_ = PendingFrame{};
}

// Reads finished frames' timestamps, oldest frame first. Every result is read only after
// GL_QUERY_RESULT_AVAILABLE said so for that query (never a blocking GL_QUERY_RESULT read); with
// `wait` (more than `latency` frames in flight, or the end of a run) the oldest frame is polled
// until its queries are available.
void PassTimer::collect(bool wait) {
  while (!pending_.empty()) {
    PendingFrame& frame = pending_.front();
    for (const auto& [startQuery, endQuery] : frame.queries)
      for (const Query* q : {&startQuery, &endQuery}) {
        GLint available = GL_FALSE;
        glGetQueryObjectiv(q->id(), GL_QUERY_RESULT_AVAILABLE, &available);
        while (!available && wait) glGetQueryObjectiv(q->id(), GL_QUERY_RESULT_AVAILABLE, &available);
        if (!available) return;
      }
    for (size_t i = 0; i < frame.queries.size(); ++i) {
      GLuint64 start = 0, stop = 0;
      glGetQueryObjectui64v(frame.queries[i].first.id(), GL_QUERY_RESULT, &start);
      glGetQueryObjectui64v(frame.queries[i].second.id(), GL_QUERY_RESULT, &stop);
      frame.timing.passes[i].ms = stop > start ? static_cast<double>(stop - start) * 1e-6 : 0.0;
      spareQueries_.push_back(std::move(frame.queries[i].first));
      spareQueries_.push_back(std::move(frame.queries[i].second));
    }
    completed_.push_back(std::move(frame.timing));
    pending_.pop_front();
    wait = false;
  }
}

std::vector<FrameTiming> PassTimer::takeCompleted() {
  if (mode_ == TimingMode::GpuQueries) collect(false);
  std::vector<FrameTiming> out;
  out.swap(completed_);
  return out;
}

std::vector<FrameTiming> PassTimer::drain() {
  while (!pending_.empty()) collect(true);
  return takeCompleted();
}

}  // namespace forest::gl
