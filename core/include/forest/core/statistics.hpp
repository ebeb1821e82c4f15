#pragma once
// Statistics of a run's per-frame times: percentiles, and how far a run's percentile can be trusted
// (a confidence interval from a moving-block bootstrap over the frames).
#include <cstdint>
#include <span>
#include <vector>

namespace forest {

// Linear-interpolated percentile q ∈ [0, 1] of the values (0 for none).
double percentile(std::vector<double> values, double q);

// A statistic of a series: "mean" or a percentile ("p50", "p95", "p99", as q = 0.5, 0.95, 0.99).
struct Statistic {
  bool mean = false;
  double q = 0.5;  // the percentile's, when not the mean
  double of(std::vector<double> values) const;
  // The frames a run needs for it: 20 beyond the percentile (n·(1 − q) ≥ 20; for a p95 400
  // frames, a p99 2000), or 20 for the mean — with fewer, the estimate rests on a handful of frames.
  int framesNeeded() const;
};
inline constexpr int kFramesBeyondPercentile = 20;

// The statistic's value on the series and its central 95% confidence interval: the 2.5th and
// 97.5th percentiles of the statistic over `resamples` moving-block bootstrap resamples (Künsch
// 1989: blocks of ⌈n^(1/3)⌉ consecutive frames, so the frame-to-frame correlation of a walk stays
// in each block). Deterministic for a given seed. An empty series gives zeros.
struct Interval {
  double value = 0.0, low = 0.0, high = 0.0;
};
Interval bootstrapInterval(std::span<const double> series, const Statistic& statistic, int resamples = 2000,
                           std::uint64_t seed = 0x5eed);

}  // namespace forest
