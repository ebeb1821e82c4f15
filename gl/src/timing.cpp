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

PassTimer::Slot& PassTimer::current() {
  if (current_ == kNone) throw Error("PassTimer: a pass outside beginFrame/endFrame");
  return slots_[current_];
}

void PassTimer::beginFrame() {
  if (current_ != kNone) throw Error("PassTimer::beginFrame: the previous frame was not ended");
  if (free_.empty()) {
    free_.push_back(slots_.size());
    slots_.emplace_back();
  }
  current_ = free_.back();
  free_.pop_back();
  Slot& slot = slots_[current_];
  slot.timing.frame = frameNumber_++;
  slot.timing.cpuFrameMs = 0.0;
  slot.timing.passes.clear();
  open_.clear();
  if (mode_ == TimingMode::Profiling) glFinish();
  frameStart_ = Clock::now();
}

void PassTimer::begin(const std::string& pass) {
  Slot& slot = current();
  slot.timing.passes.push_back({pass, 0.0});
  const size_t index = slot.timing.passes.size() - 1;
  // Profiling: the GPU is idle here (beginFrame or the previous pass's end finished it), so the
  // clock alone starts the pass.
  if (mode_ == TimingMode::GpuQueries) {
    if (slot.queries.size() <= index) slot.queries.emplace_back(Query(GL_TIMESTAMP), Query(GL_TIMESTAMP));
    glQueryCounter(slot.queries[index].first.id(), GL_TIMESTAMP);
  }
  open_.push_back({index, Clock::now()});
}

void PassTimer::end() {
  if (open_.empty()) throw Error("PassTimer::end without begin");
  const OpenPass pass = open_.back();
  open_.pop_back();
  Slot& slot = current();
  if (mode_ == TimingMode::Profiling) {
    glFinish();
    slot.timing.passes[pass.recordIndex].ms = millisecondsBetween(pass.start, Clock::now());
  } else {
    glQueryCounter(slot.queries[pass.recordIndex].second.id(), GL_TIMESTAMP);
  }
}

void PassTimer::endFrame() {
  Slot& slot = current();
  if (!open_.empty())
    throw Error("PassTimer::endFrame with pass '" + slot.timing.passes[open_.back().recordIndex].pass + "' still open");
  if (mode_ == TimingMode::Profiling) glFinish();
  slot.timing.cpuFrameMs = millisecondsBetween(frameStart_, Clock::now());
  if (mode_ == TimingMode::Profiling) {
    done_.push_back(current_);
  } else {
    inFlight_.push_back(current_);
  }
  current_ = kNone;
  if (mode_ == TimingMode::GpuQueries) collect(static_cast<int>(inFlight_.size()) > latency_);
}

// Reads finished frames' timestamps, oldest frame first. Every result is read only after
// GL_QUERY_RESULT_AVAILABLE said so for that query (never a blocking GL_QUERY_RESULT read); with
// `wait` (more than `latency` frames in flight, or the end of a run) the oldest frame is polled
// until its queries are available.
void PassTimer::collect(bool wait) {
  while (!inFlight_.empty()) {
    Slot& frame = slots_[inFlight_.front()];
    const size_t passes = frame.timing.passes.size();
    for (size_t i = 0; i < passes; ++i)
      for (const Query* q : {&frame.queries[i].first, &frame.queries[i].second}) {
        GLint available = GL_FALSE;
        glGetQueryObjectiv(q->id(), GL_QUERY_RESULT_AVAILABLE, &available);
        while (!available && wait) glGetQueryObjectiv(q->id(), GL_QUERY_RESULT_AVAILABLE, &available);
        if (!available) return;
      }
    for (size_t i = 0; i < passes; ++i) {
      GLuint64 start = 0, stop = 0;
      glGetQueryObjectui64v(frame.queries[i].first.id(), GL_QUERY_RESULT, &start);
      glGetQueryObjectui64v(frame.queries[i].second.id(), GL_QUERY_RESULT, &stop);
      frame.timing.passes[i].ms = stop > start ? static_cast<double>(stop - start) * 1e-6 : 0.0;
    }
    done_.push_back(inFlight_.front());
    inFlight_.erase(inFlight_.begin());  // a few frames at most
    wait = false;
  }
}

std::vector<FrameTiming> PassTimer::takeCompleted() {
  if (mode_ == TimingMode::GpuQueries) collect(false);
  std::vector<FrameTiming> out;
  for (size_t slot : done_) {
    out.push_back(slots_[slot].timing);
    free_.push_back(slot);
  }
  done_.clear();
  return out;
}

bool PassTimer::takeOldestCompleted(FrameTiming& into) {
  if (mode_ == TimingMode::GpuQueries) collect(false);
  if (done_.empty()) return false;
  into = slots_[done_.front()].timing;
  free_.push_back(done_.front());
  done_.erase(done_.begin());
  return true;
}

std::vector<FrameTiming> PassTimer::drain() {
  while (!inFlight_.empty()) collect(true);
  return takeCompleted();
}

}  // namespace forest::gl
