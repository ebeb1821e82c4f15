// Budget verdicts (core/budget.hpp, core/statistics.hpp) on series drawn from known distributions:
// the interval holds the distribution's own percentile (a closed form), the verdict follows the
// interval exactly, a run too short for its percentile says so, and limits in reference frames give
// one verdict on a machine twice as slow.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "forest/core/budget.hpp"
#include "forest/core/error.hpp"
#include "forest/core/random.hpp"
#include "forest/core/statistics.hpp"

namespace forest {
namespace {

// n frame times from an exponential distribution of mean `mean` ms plus a floor of 10 ms:
// its q-percentile is 10 − mean·ln(1 − q).
std::vector<double> exponentialFrames(int n, double mean, std::uint64_t seed) {
  SplitMix64 random(seed);
  std::vector<double> frames;
  for (int i = 0; i < n; ++i) frames.push_back(10.0 - mean * std::log(1.0 - random.unit()));
  return frames;
}
double exponentialPercentile(double mean, double q) { return 10.0 - mean * std::log(1.0 - q); }

TEST(BudgetStatistics, PercentileInterpolatesBetweenRanks) {
  EXPECT_DOUBLE_EQ(percentile({1.0, 2.0, 3.0, 4.0}, 0.5), 2.5);
  EXPECT_DOUBLE_EQ(percentile({4.0, 1.0, 3.0, 2.0}, 1.0), 4.0);
  EXPECT_DOUBLE_EQ(percentile({}, 0.5), 0.0);
  EXPECT_THROW(percentile({1.0, 2.0}, 50.0), Error);  // a percent, not a share: refused, not read past the end
  EXPECT_EQ((Statistic{false, 0.95}).framesNeeded(), 400);  // 20 frames beyond the p95
  EXPECT_EQ((Statistic{false, 0.99}).framesNeeded(), 2000);
  EXPECT_EQ((Statistic{false, 0.5}).framesNeeded(), 40);
  EXPECT_EQ((Statistic{true, 0.0}).framesNeeded(), 20);
}

TEST(BudgetStatistics, TheIntervalHoldsTheTruePercentileAsOftenAsItClaims) {
  // 40 independent runs of 1000 frames: a 95% interval misses the true p95 in about 2 of them;
  // 6 or more misses has probability < 0.2% (binomial, n = 40, p = 0.05). Each half of the interval
  // is, on average, the normal approximation's 1.96 standard errors of a sample quantile:
  // √(q(1 − q)/n) / f(x_q), with the density f(x_q) = (1 − q)/mean for the exponential — 1.35 ms —
  // within ±30% (the bootstrap of a quantile is coarse, the average over 40 runs is not).
  int misses = 0;
  const double truth = exponentialPercentile(5.0, 0.95);
  const double halfWidth = 1.96 * std::sqrt(0.95 * 0.05 / 1000.0) / (0.05 / 5.0);
  double below = 0.0, above = 0.0;
  for (std::uint64_t run = 0; run < 40; ++run) {
    const std::vector<double> frames = exponentialFrames(1000, 5.0, 1000 + run);
    const Interval i = bootstrapInterval(frames, {false, 0.95}, 1000, run);
    EXPECT_LE(i.low, i.value);
    EXPECT_LE(i.value, i.high);
    misses += truth < i.low || truth > i.high ? 1 : 0;
    below += (i.value - i.low) / 40.0;
    above += (i.high - i.value) / 40.0;
  }
  EXPECT_LE(misses, 5);
  EXPECT_NEAR(below, halfWidth, 0.3 * halfWidth);
  EXPECT_NEAR(above, halfWidth, 0.3 * halfWidth);
}

TEST(BudgetVerdict, FollowsTheIntervalExactly) {
  const std::vector<double> frames = exponentialFrames(1000, 5.0, 7);
  const double truth = exponentialPercentile(5.0, 0.95);  // 24.98 ms
  // Far above and far below the true p95, and at it.
  const LimitVerdict above = judgeLimit(frames, {"frame", "p95", 1.3 * truth}, BudgetUnit::Milliseconds, 0.0);
  const LimitVerdict below = judgeLimit(frames, {"frame", "p95", 0.7 * truth}, BudgetUnit::Milliseconds, 0.0);
  const LimitVerdict at = judgeLimit(frames, {"frame", "p95", truth}, BudgetUnit::Milliseconds, 0.0);
  EXPECT_EQ(above.verdict, Verdict::Holds);
  EXPECT_EQ(below.verdict, Verdict::Over);
  EXPECT_EQ(at.verdict, Verdict::Inconclusive);
  // Every limit across the range: the verdict is the interval's, to the boundary.
  const Interval i = at.measured;
  for (double limit = 0.8 * truth; limit <= 1.2 * truth; limit += 0.01 * truth) {
    const LimitVerdict v = judgeLimit(frames, {"frame", "p95", limit}, BudgetUnit::Milliseconds, 0.0);
    const Verdict expected = i.low > limit ? Verdict::Over : i.high <= limit ? Verdict::Holds : Verdict::Inconclusive;
    EXPECT_EQ(v.verdict, expected) << "limit " << limit << " interval [" << i.low << ", " << i.high << "]";
  }
  EXPECT_EQ(judgeLimit(frames, {"frame", "p95", i.high}, BudgetUnit::Milliseconds, 0.0).verdict, Verdict::Holds);
  // An inconclusive verdict names more frames than the run had (a narrower interval decides it).
  const LimitVerdict near = judgeLimit(frames, {"frame", "p95", 0.5 * (i.value + i.high)}, BudgetUnit::Milliseconds, 0.0);
  ASSERT_EQ(near.verdict, Verdict::Inconclusive);
  EXPECT_GT(near.framesToDecide, 1000);
}

TEST(BudgetVerdict, ARunTooShortForItsPercentileSaysSo) {
  const std::vector<double> frames = exponentialFrames(399, 5.0, 3);
  const LimitVerdict p95 = judgeLimit(frames, {"frame", "p95", 1e6}, BudgetUnit::Milliseconds, 0.0);
  EXPECT_EQ(p95.verdict, Verdict::TooShort);
  EXPECT_EQ(p95.framesToDecide, 400);
  const std::vector<double> enough = exponentialFrames(400, 5.0, 3);
  EXPECT_EQ(judgeLimit(enough, {"frame", "p95", 1e6}, BudgetUnit::Milliseconds, 0.0).verdict, Verdict::Holds);
  EXPECT_EQ(judgeLimit(frames, {"frame", "p99", 1e6}, BudgetUnit::Milliseconds, 0.0).verdict, Verdict::TooShort);
  EXPECT_EQ(judgeLimit(frames, {"frame", "mean", 1e6}, BudgetUnit::Milliseconds, 0.0).verdict, Verdict::Holds);
}

TEST(BudgetVerdict, LimitsInReferenceFramesTravelBetweenMachines) {
  // The same run on a machine twice as slow: every frame and the reference frame take twice as long.
  const std::vector<double> fast = exponentialFrames(1000, 5.0, 11);
  std::vector<double> slow = fast;
  for (double& ms : slow) ms *= 2.0;
  const double referenceFast = 8.0, referenceSlow = 16.0;
  for (double limit : {2.5, 3.0, 3.2, 4.0}) {  // reference frames (the p95 is ~3.1 of them)
    const BudgetLimit l{"frame", "p95", limit};
    const LimitVerdict a = judgeLimit(fast, l, BudgetUnit::ReferenceFrames, referenceFast);
    const LimitVerdict b = judgeLimit(slow, l, BudgetUnit::ReferenceFrames, referenceSlow);
    EXPECT_EQ(a.verdict, b.verdict) << limit;
    EXPECT_DOUBLE_EQ(b.limitMs, 2.0 * a.limitMs);
  }
  // In milliseconds the slow machine is over a limit the fast one holds.
  const BudgetLimit ms{"frame", "p95", 30.0};
  EXPECT_EQ(judgeLimit(fast, ms, BudgetUnit::Milliseconds, 0.0).verdict, Verdict::Holds);
  EXPECT_EQ(judgeLimit(slow, ms, BudgetUnit::Milliseconds, 0.0).verdict, Verdict::Over);
}

TEST(BudgetFile, UnitIsMillisecondsOrReferenceFrames) {
  EXPECT_EQ(parseBudget("[frame]\np50 = 10.0\n", "b.toml").unit, BudgetUnit::Milliseconds);
  EXPECT_EQ(parseBudget("unit = \"reference\"\n[frame]\np50 = 1.5\n", "b.toml").unit, BudgetUnit::ReferenceFrames);
  try {
    parseBudget("unit = \"seconds\"\n[frame]\np50 = 1.5\n", "b.toml");
    ADD_FAILURE() << "accepted unit = seconds";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("b.toml:1"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("reference"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace forest
