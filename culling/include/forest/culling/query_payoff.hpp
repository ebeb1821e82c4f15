#pragma once
// Whether occlusion queries pay for themselves, measured (beyond the papers). A query costs about
// what drawing its node would (a far tree's query draws its 48 triangles), and on a software
// renderer each wait for results drains the whole pipeline; where most of the frustum is visible
// (an open view over a flat canopy) drawing the frustum's objects untested is then the faster
// frame. Guthe, Balázs and Klein ("Near optimal hierarchical culling", EG 2006) decide this per
// node from a calibrated cost model; this unit decides it per frame from the frames' measured
// times, which need no calibration and follow the machine:
//   - it runs the asked strategy (chc++) and keeps the median of its last `window` measured
//     frames;
//   - now and then it probes the other way — `probeFrames` frames of frustum culling — and
//     switches when the probe's median is below the current way's median by more than `margin`;
//     a probe that does not switch, its median k times the current way's, multiplies the wait
//     before the next one by 2·max(1, k) (from `firstProbe` to at most `maxProbeInterval`
//     frames), so a way that keeps losing, or loses by far, costs ever fewer frames;
//   - when the current way's median climbs above the other way's last known median (the view
//     changed: the walker came down from the hill into the stand), it probes at once.
// Both ways are exact (frustum culling draws everything in the frustum), so the choice changes
// only the time. Times may arrive frames late (GL timer queries): decisions wait for them.
#include <cstdint>
#include <deque>
#include <vector>

#include "forest/culling/occlusion_culler.hpp"

namespace forest::culling {

struct QueryPayoffSettings {
  int window = 5;               // frames whose median stands for the current way's cost, ≥ 1
  int probeFrames = 2;          // frames of one probe, ≥ 1 (their median: one cold frame does not decide)
  int firstProbe = 10;          // frames before the first probe, and after a switch, ≥ 1
  int maxProbeInterval = 480;   // the longest wait between probes, ≥ firstProbe
  double margin = 0.05;         // a switch needs the other way cheaper by this share, [0, 1)
};

class QueryPayoff {
 public:
  explicit QueryPayoff(QueryPayoffSettings settings = {});  // throws Error on settings out of range

  // The strategy for frame `frame` (the caller's numbers, increasing from call to call; frames
  // between two calls did not take part): `asked`, or frustum culling while queries do not pay
  // or during a probe. Strategies without queries (none, frustum) are returned as asked and take
  // no part.
  CullingStrategy next(std::uint64_t frame, CullingStrategy asked);
  // The measured time of frame `frame` (a frame next() was called for); frames may be recorded
  // late and in any order; a frame not recorded within 64 frames is forgotten.
  void record(std::uint64_t frame, double milliseconds);
  // Whether the settled way is frustum culling (queries found not to pay).
  bool fallenBack() const { return fallenBack_; }
  int switches() const { return switches_; }
  int probes() const { return probes_; }
  // Starts again: queries, first probe after `firstProbe` frames.
  void reset();

 private:
  struct Planned {
    std::uint64_t frame;
    bool frustum;  // ran frustum culling
    bool probe;    // part of a probe
  };
  void finishProbe();  // the probe's frames are all in (or forgotten): switch or not, plan the next
  double median(const std::vector<double>& values) const;

  QueryPayoffSettings settings_;
  std::uint64_t nextFrame_ = 0;
  bool fallenBack_ = false;
  int probeLeft_ = 0;                // probe frames still to run
  std::vector<double> probeTimes_;   // the running probe's measured frames
  int probeOutstanding_ = 0;         // probe frames run but not yet recorded
  std::uint64_t nextProbeAt_ = 0;
  int interval_ = 0;                 // frames from the end of a probe to the next
  std::vector<double> recent_;       // the settled way's last `window` frames, oldest first
  double otherCost_ = -1.0;          // the other way's median when last measured (< 0: never)
  std::deque<Planned> planned_;      // frames run and not yet recorded
  int switches_ = 0, probes_ = 0;
};

}  // namespace forest::culling
