#pragma once
// Per-pass frame timing. Two modes (DESIGN §5, "Speed"):
//   GpuQueries — GL_TIMESTAMP queries around each pass, read back `latency` frames later so the
//                CPU never waits (for GPUs; llvmpipe's timer results are unreliable);
//   Profiling  — glFinish + steady clock around each pass (for llvmpipe; serialises the pipeline).
// Usage per frame: beginFrame(); { auto s = timer.scope("shadow"); ... } endFrame(); then
// takeCompleted() returns the frames whose times are known.
#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include "forest/core/enum_names.hpp"
#include "forest/gl/objects.hpp"

namespace forest::gl {

enum class TimingMode { GpuQueries, Profiling };
inline constexpr EnumNames<TimingMode, 2> kTimingModeNames{
    "timing", {{{TimingMode::Profiling, "profile"}, {TimingMode::GpuQueries, "queries"}}}};

struct PassTime {
  std::string pass;
  double ms = 0.0;
};

struct FrameTiming {
  std::uint64_t frame = 0;
  double cpuFrameMs = 0.0;  // wall time from beginFrame to endFrame (includes glFinish in Profiling)
  std::vector<PassTime> passes;
};

class PassTimer {
 public:
  // latency: GpuQueries frames in flight before the timer waits (polling availability) for the
  // oldest; firstFrame: the number FrameTiming::frame starts at.
  explicit PassTimer(TimingMode mode, int latency = 3, std::uint64_t firstFrame = 0);

  class Scope {
   public:
    explicit Scope(PassTimer& timer) : timer_(&timer) {}
    ~Scope() { timer_->end(); }
    Scope(const Scope&) = delete;
    Scope& operator=(const Scope&) = delete;

   private:
    PassTimer* timer_;
  };

  void beginFrame();
  void begin(const std::string& pass);
  void end();
  Scope scope(const std::string& pass) {
    begin(pass);
    return Scope(*this);
  }
  void endFrame();

  // Frames whose pass times are all known, oldest first; each is returned once.
  std::vector<FrameTiming> takeCompleted();
  // The oldest of them into `into` (its storage reused: no allocation once it has held a frame);
  // false when none is known yet.
  bool takeOldestCompleted(FrameTiming& into);
  // Waits for every frame still in flight (end of a run), then returns all of them.
  std::vector<FrameTiming> drain();
  TimingMode mode() const { return mode_; }

 private:
  // A frame's record and its timestamp queries (start, end per pass), reused from frame to frame:
  // a steady-state frame allocates nothing and creates no GL object (DESIGN §9).
  struct Slot {
    FrameTiming timing;
    std::vector<std::pair<Query, Query>> queries;
  };
  struct OpenPass {
    size_t recordIndex;
    std::chrono::steady_clock::time_point start;
  };
  static constexpr size_t kNone = static_cast<size_t>(-1);

  TimingMode mode_;
  int latency_;
  std::uint64_t frameNumber_ = 0;
  std::chrono::steady_clock::time_point frameStart_;
  std::vector<Slot> slots_;
  std::vector<size_t> free_;      // slots not in use
  std::vector<size_t> inFlight_;  // GpuQueries: ended frames waiting for their timestamps, oldest first
  std::vector<size_t> done_;      // frames whose times are known, not yet taken, oldest first
  size_t current_ = kNone;        // the frame being recorded
  std::vector<OpenPass> open_;
  Slot& current();
  void collect(bool wait);
};

}  // namespace forest::gl
