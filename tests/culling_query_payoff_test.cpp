// QueryPayoff (culling/query_payoff.hpp): the frames each way runs, worked out by hand from the
// rules its header states, for frames whose times are given by the way they ran.
#include <gtest/gtest.h>

#include <deque>
#include <functional>
#include <utility>

#include "forest/core/error.hpp"
#include "forest/culling/query_payoff.hpp"

namespace {

using forest::culling::CullingStrategy;
using forest::culling::QueryPayoff;
using forest::culling::QueryPayoffSettings;

// Runs `frames` frames asking chc++; frame f costs cost(f, ran frustum); each time is recorded
// `delay` frames after its frame. Returns the way each frame ran (true: frustum).
std::vector<bool> run(QueryPayoff& payoff, int frames, const std::function<double(int, bool)>& cost, int delay = 0) {
  std::vector<bool> frustum;
  std::deque<std::pair<int, double>> late;
  for (int f = 0; f < frames; ++f) {
    const CullingStrategy s = payoff.next(static_cast<std::uint64_t>(f), CullingStrategy::ChcPlusPlus);
    EXPECT_TRUE(s == CullingStrategy::ChcPlusPlus || s == CullingStrategy::Frustum);
    frustum.push_back(s == CullingStrategy::Frustum);
    late.emplace_back(f, cost(f, frustum.back()));
    while (!late.empty() && late.front().first + delay <= f) {
      payoff.record(static_cast<std::uint64_t>(late.front().first), late.front().second);
      late.pop_front();
    }
  }
  return frustum;
}

int count(const std::vector<bool>& ways, bool frustum, int from = 0, int to = -1) {
  int n = 0;
  for (int f = from; f < (to < 0 ? static_cast<int>(ways.size()) : to); ++f) n += ways[static_cast<std::size_t>(f)] == frustum;
  return n;
}

// Defaults: window 5, probes of 2 frames, the first after 10, then 2·max(1, loss) times longer up
// to 480, margin 5%. Here the losing way costs twice the other: each wait is 4 times the last.
TEST(QueryPayoff, FallsBackToFrustumCullingWhenQueriesCostMore) {
  QueryPayoff payoff;
  const auto ways = run(payoff, 300, [](int, bool frustum) { return frustum ? 5.0 : 10.0; });
  // chc++ in 0–9; the probe 10–11 finds frustum culling cheaper and switches; queries are probed
  // at 22–23 (10 frames on), 64–65 (40 after that probe's end), 226–227 (160): 10 + 3 × 2 frames.
  EXPECT_EQ(count(ways, false), 16);
  EXPECT_EQ(count(ways, false, 0, 10), 10);
  EXPECT_EQ(count(ways, true, 10, 22), 12);
  EXPECT_FALSE(ways[22] || ways[23] || ways[64] || ways[65] || ways[226] || ways[227]);
  EXPECT_TRUE(payoff.fallenBack());
  EXPECT_EQ(payoff.switches(), 1);
  EXPECT_EQ(payoff.probes(), 4);
}

TEST(QueryPayoff, KeepsQueriesWhenTheyPayAndProbesEverMoreRarely) {
  QueryPayoff payoff;
  const auto ways = run(payoff, 300, [](int, bool frustum) { return frustum ? 10.0 : 5.0; });
  // Probes at 10–11, then 40 frames after its end (52–53), then 160 (214–215): 6 frames.
  EXPECT_EQ(count(ways, true), 6);
  EXPECT_TRUE(ways[10] && ways[11] && ways[52] && ways[53] && ways[214] && ways[215]);
  EXPECT_FALSE(payoff.fallenBack());
  EXPECT_EQ(payoff.switches(), 0);
}

TEST(QueryPayoff, EqualCostsNeverSwitch) {
  QueryPayoff payoff;
  (void)run(payoff, 1000, [](int, bool) { return 7.0; });
  EXPECT_EQ(payoff.switches(), 0);  // a switch needs the other way cheaper by the margin
  EXPECT_FALSE(payoff.fallenBack());
  EXPECT_EQ(payoff.probes(), 6);  // waits 10, 20, 40, 80, 160, 320 (no loss: doubling) fit 1000 frames
}

TEST(QueryPayoff, ProbesAtOnceWhenTheViewMakesTheCurrentWayDear) {
  QueryPayoff payoff;
  // Frustum culling is cheaper until frame 100, then costs twice what queries do.
  const auto ways = run(payoff, 200, [](int f, bool frustum) { return frustum ? (f < 100 ? 5.0 : 20.0) : 10.0; });
  // Fallen back at 11 (queries probed at 22 and 64); from 100 the window's median passes
  // queries' last probe (10 × 1.05) once 3 of its 5 frames cost 20 (after 102's record), a probe
  // runs 103–104 and switches back; frustum culling's next probe is at 115.
  EXPECT_TRUE(ways[99]);
  EXPECT_EQ(count(ways, true, 100, 103), 3);
  EXPECT_EQ(count(ways, false, 103, 115), 12);
  EXPECT_TRUE(ways[115] && ways[116]);
  EXPECT_FALSE(payoff.fallenBack());
  EXPECT_EQ(payoff.switches(), 2);
}

TEST(QueryPayoff, DecidesOnLateTimes) {
  QueryPayoff payoff;
  const int delay = 3;  // timer queries read three frames later
  const auto ways = run(payoff, 300, [](int, bool frustum) { return frustum ? 5.0 : 10.0; }, delay);
  // As without delay, each decision up to `delay` frames later: the switch and the three probes.
  EXPECT_GE(count(ways, false), 16);
  EXPECT_LE(count(ways, false), 16 + 4 * delay);
  EXPECT_TRUE(payoff.fallenBack());
  EXPECT_EQ(payoff.switches(), 1);
}

TEST(QueryPayoff, TimesNeverRecordedNeverSwitch) {
  QueryPayoff payoff;
  for (std::uint64_t f = 0; f < 1000; ++f) (void)payoff.next(f, CullingStrategy::ChcPlusPlus);
  EXPECT_FALSE(payoff.fallenBack());
  EXPECT_GT(payoff.probes(), 1);  // a probe whose frames were forgotten ends, and the next follows
  payoff.record(5, 1.0);          // long forgotten: ignored
  payoff.record(999, std::numeric_limits<double>::quiet_NaN());
  EXPECT_FALSE(payoff.fallenBack());
}

TEST(QueryPayoff, StrategiesWithoutQueriesTakeNoPart) {
  QueryPayoff payoff;
  std::uint64_t frame = 0;
  for (int k = 0; k < 100; ++k) {
    EXPECT_EQ(payoff.next(frame++, CullingStrategy::None), CullingStrategy::None);
    EXPECT_EQ(payoff.next(frame++, CullingStrategy::Frustum), CullingStrategy::Frustum);
  }
  EXPECT_EQ(payoff.probes(), 0);
  // A query strategy other than chc++ takes part too: the probe due since frame 10 runs first.
  int frustum = 0;
  for (int k = 0; k < 40; ++k) frustum += payoff.next(frame++, CullingStrategy::Chc) == CullingStrategy::Frustum;
  EXPECT_EQ(frustum, 2);
  EXPECT_THROW(payoff.next(5, CullingStrategy::ChcPlusPlus), forest::Error) << "frames go forward";
}

// Frames the caller leaves out (another strategy asked, a frame frozen) count in the schedule.
TEST(QueryPayoff, FramesLeftOutCountInTheSchedule) {
  QueryPayoff payoff;
  int frustum = 0;
  for (std::uint64_t f = 0; f < 60; f += 2) frustum += payoff.next(f, CullingStrategy::ChcPlusPlus) == CullingStrategy::Frustum;
  EXPECT_EQ(frustum, 2);  // the probe from frame 10 on: frames 10 and 12
}

TEST(QueryPayoff, RejectsSettingsOutOfRange) {
  EXPECT_THROW(QueryPayoff({.window = 0}), forest::Error);
  EXPECT_THROW(QueryPayoff({.probeFrames = 0}), forest::Error);
  EXPECT_THROW(QueryPayoff({.firstProbe = 0}), forest::Error);
  EXPECT_THROW(QueryPayoff({.firstProbe = 10, .maxProbeInterval = 5}), forest::Error);
  EXPECT_THROW(QueryPayoff({.margin = 1.0}), forest::Error);
  EXPECT_THROW(QueryPayoff({.margin = -0.1}), forest::Error);
}

}  // namespace
