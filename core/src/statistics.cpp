#include "forest/core/statistics.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

#include "forest/core/error.hpp"
#include "forest/core/random.hpp"

namespace forest {

double percentile(std::vector<double> values, double q) {
  if (!(q >= 0.0 && q <= 1.0)) throw Error("percentile " + std::to_string(q) + ": expected q in [0, 1]");
  if (values.empty()) return 0.0;
  const double position = q * static_cast<double>(values.size() - 1);
  const std::size_t below = static_cast<std::size_t>(position);
  // The two order statistics around the position, without a full sort (the bootstrap asks often).
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(below), values.end());
  const double low = values[below];
  const double high = below + 1 < values.size() ? *std::min_element(values.begin() + static_cast<std::ptrdiff_t>(below) + 1, values.end()) : low;
  return low + (high - low) * (position - static_cast<double>(below));
}

double Statistic::of(std::vector<double> values) const {
  if (!mean) return percentile(std::move(values), q);
  if (values.empty()) return 0.0;
  return std::accumulate(values.begin(), values.end(), 0.0) / static_cast<double>(values.size());
}

int Statistic::framesNeeded() const {
  if (mean) return kFramesBeyondPercentile;
  return static_cast<int>(std::ceil(kFramesBeyondPercentile / (1.0 - q) - 1e-9));
}

Interval bootstrapInterval(std::span<const double> series, const Statistic& statistic, int resamples, std::uint64_t seed) {
  Interval interval;
  const std::size_t n = series.size();
  if (n == 0) return interval;
  interval.value = statistic.of({series.begin(), series.end()});
  const std::size_t block = std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil(std::cbrt(static_cast<double>(n)))));
  const std::size_t starts = n - std::min(block, n) + 1;  // blocks that fit in the series
  SplitMix64 random(seed);
  std::vector<double> resample(n), values;
  values.reserve(static_cast<std::size_t>(resamples));
  for (int r = 0; r < resamples; ++r) {
    for (std::size_t filled = 0; filled < n;) {
      const std::size_t start = static_cast<std::size_t>(random.unit() * static_cast<double>(starts));
      for (std::size_t k = 0; k < block && filled < n; ++k) resample[filled++] = series[std::min(start + k, n - 1)];
    }
    values.push_back(statistic.of(resample));
  }
  interval.low = percentile(values, 0.025);
  interval.high = percentile(values, 0.975);
  return interval;
}

}  // namespace forest
