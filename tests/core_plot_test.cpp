// Plot ranges: one series far above the others is clipped at the top edge, so that the others keep
// the panel's height (the culling plot's stop-and-wait at 10× the other strategies); series of
// like size are shown whole. Expected values from the rule's closed form on the case's numbers.
#include <gtest/gtest.h>

#include <cmath>

#include "forest/core/plot.hpp"

namespace forest {
namespace {

PlotSeries series(const std::string& label, std::initializer_list<double> ys) {
  PlotSeries s;
  s.label = label;
  double x = 0.0;
  for (double y : ys) s.points.emplace_back(x++, y);
  return s;
}

TEST(PlotYRange, OneSeriesTenTimesTheOthersIsClippedAtOneAndAHalfTimesTheNextPeak) {
  PlotPanel panel;
  panel.series = {series("frustum", {10, 20, 18}), series("chc++", {5, 8, 6}), series("stop-and-wait", {150, 210, 190})};
  const PlotYRange r = plotYRange(panel);
  ASSERT_NE(r.clipped, nullptr);
  EXPECT_EQ(r.clipped->label, "stop-and-wait");
  EXPECT_DOUBLE_EQ(r.clippedPeak, 210.0);
  EXPECT_DOUBLE_EQ(r.low, 0.0);
  EXPECT_DOUBLE_EQ(r.high, 1.05 * 1.5 * 20.0);  // the other series' peak, 20, with the headroom and the 5% margin
}

TEST(PlotYRange, SeriesOfLikeSizeAreShownWhole) {
  PlotPanel panel;
  panel.series = {series("a", {10, 20}), series("b", {30, 79})};  // levels 20 and 79 < 4 × 20: not clipped
  const PlotYRange r = plotYRange(panel);
  EXPECT_EQ(r.clipped, nullptr);
  EXPECT_DOUBLE_EQ(r.high, 1.05 * 79.0);
  PlotPanel single;
  single.series = {series("only", {3, 400})};  // nothing to compare with: whole
  EXPECT_EQ(plotYRange(single).clipped, nullptr);
  EXPECT_DOUBLE_EQ(plotYRange(single).high, 1.05 * 400.0);
}

TEST(PlotYRange, ASpikeOfOneSeriesClipsNothing) {
  PlotPanel panel;
  panel.series = {series("first frame", {100, 10, 10, 10}), series("b", {20, 20, 20})};  // levels 10 and 20
  const PlotYRange r = plotYRange(panel);
  EXPECT_EQ(r.clipped, nullptr);
  EXPECT_DOUBLE_EQ(r.high, 1.05 * 100.0);
}

TEST(PlotYRange, NegativeValuesAndEmptyPanelsKeepAValidRange) {
  PlotPanel panel;
  panel.series = {series("a", {-10, 10}), series("b", {-5, 200})};  // levels 10, 200: 210 > 4 × 20 above the lowest
  const PlotYRange r = plotYRange(panel);
  ASSERT_NE(r.clipped, nullptr);
  EXPECT_DOUBLE_EQ(r.low, -10.0);
  EXPECT_DOUBLE_EQ(r.high, -10.0 + 1.05 * 1.5 * 20.0);
  const PlotYRange empty = plotYRange(PlotPanel{});
  EXPECT_LT(empty.low, empty.high);
  EXPECT_TRUE(std::isfinite(empty.high));
}

}  // namespace
}  // namespace forest
