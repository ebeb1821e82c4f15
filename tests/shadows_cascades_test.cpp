// Cascade splits (Zhang et al. 2006, eq. 4) against their closed forms on the case's inputs: λ = 0
// the uniform split, λ = 1 the logarithmic one (equal depth ratios), λ = ½ their mean; every K
// covers [near, far] without a gap, strictly increasing; bad inputs are refused by name.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "forest/core/error.hpp"
#include "forest/shadows/cascades.hpp"

namespace forest::shadows {
namespace {

TEST(CascadeSplits, MatchTheUniformTheLogarithmicAndTheirMean) {
  const double near = 0.5, far = 2000.0;
  for (int k = 1; k <= kMaxCascades; ++k) {
    const SplitDepths uniform = cascadeSplits(near, far, k, 0.0), logarithmic = cascadeSplits(near, far, k, 1.0),
                              half = cascadeSplits(near, far, k, 0.5);
    ASSERT_EQ(uniform.size(), static_cast<size_t>(k) + 1);
    for (int i = 0; i <= k; ++i) {
      const double u = near + (far - near) * i / k;               // equal lengths
      const double l = near * std::exp(std::log(far / near) * i / k);  // equal ratios z_{i+1} / z_i
      EXPECT_NEAR(uniform[static_cast<size_t>(i)], u, 1e-12 * far) << k << " " << i;
      EXPECT_NEAR(logarithmic[static_cast<size_t>(i)], l, 1e-12 * far) << k << " " << i;
      EXPECT_NEAR(half[static_cast<size_t>(i)], 0.5 * (u + l), 1e-12 * far) << k << " " << i;
    }
    // The logarithmic slices all span the same depth ratio, (far / near)^(1/K).
    for (int i = 0; i < k; ++i)
      EXPECT_NEAR(logarithmic[static_cast<size_t>(i) + 1] / logarithmic[static_cast<size_t>(i)], std::pow(far / near, 1.0 / k), 1e-12);
  }
}

TEST(CascadeSplits, CoverTheRangeWithoutGapsForAnyLambda) {
  for (double near : {1e-3, 0.2, 10.0})
    for (double far : {near * 1.0001, near * 50.0, near * 1e7})
      for (int k = 1; k <= kMaxCascades; ++k)
        for (double lambda : {0.0, 0.3, 0.75, 1.0}) {
          const SplitDepths z = cascadeSplits(near, far, k, lambda);
          EXPECT_EQ(z.front(), near);  // exactly: slice 0 starts where the view does
          EXPECT_EQ(z.back(), far);    // and the last ends at z_f
          for (size_t i = 0; i + 1 < z.size(); ++i) EXPECT_LT(z[i], z[i + 1]) << near << " " << far << " " << k << " " << lambda;
        }
}

SplitDepths splitsOf(std::initializer_list<double> z) {
  SplitDepths out;
  out.cascades = static_cast<int>(z.size()) - 1;
  size_t i = 0;
  for (double v : z) out[i++] = v;
  return out;
}

// Over time each inner split moves a fifth of the way in log depth: z' · (z / z')^0.2.
TEST(CascadeSplits, SmoothedSplitsMoveAFifthOfTheWayInLogDepth) {
  const SplitDepths previous = splitsOf({0.2, 4.0, 20.0, 80.0, 300.0});
  const SplitDepths target = splitsOf({0.2, 8.0, 30.0, 100.0, 320.0});
  const SplitDepths z = smoothSplits(target, previous);
  EXPECT_EQ(z.front(), 0.2);
  EXPECT_EQ(z.back(), 320.0);
  for (size_t i = 1; i < 4; ++i) EXPECT_NEAR(z[i], previous[i] * std::pow(target[i] / previous[i], 0.2), 1e-12 * z[i]) << i;
  // Without the last frame's splits (a cut, another K): the target itself.
  const SplitDepths fresh = smoothSplits(target, SplitDepths{});
  for (size_t i = 0; i < 5; ++i) EXPECT_EQ(fresh[i], target[i]) << i;
}

// z_f falls from 300 to 25 m: split 1 smooths to 10 · 0.5^0.2, split 2's smoothed value would pass
// z_f and takes its target 8, below split 1: it goes halfway from split 1 to z_f, and so does split 3
// (its target 15 is then below split 2). No slice is empty.
TEST(CascadeSplits, ASplitThatWouldPassTheOneBelowGoesHalfwayToTheFarEnd) {
  const SplitDepths previous = splitsOf({0.2, 10.0, 40.0, 120.0, 300.0});
  const SplitDepths target = splitsOf({0.2, 5.0, 8.0, 15.0, 25.0});
  const SplitDepths z = smoothSplits(target, previous);
  const double z1 = 10.0 * std::pow(0.5, 0.2), z2 = 0.5 * (z1 + 25.0), z3 = 0.5 * (z2 + 25.0);
  EXPECT_NEAR(z[1], z1, 1e-12 * z1);
  EXPECT_NEAR(z[2], z2, 1e-12 * z2);
  EXPECT_NEAR(z[3], z3, 1e-12 * z3);
  EXPECT_EQ(z[4], 25.0);
  for (size_t i = 0; i < 4; ++i) EXPECT_LT(z[i], z[i + 1]) << "slice " << i << " is empty";
}

TEST(CascadeSplits, RefuseBadInputs) {
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  EXPECT_THROW(cascadeSplits(0.0, 100.0, 2, 0.5), InputError);
  EXPECT_THROW(cascadeSplits(10.0, 10.0, 2, 0.5), InputError);
  EXPECT_THROW(cascadeSplits(10.0, 5.0, 2, 0.5), InputError);
  EXPECT_THROW(cascadeSplits(nan, 100.0, 2, 0.5), InputError);
  EXPECT_THROW(cascadeSplits(1.0, inf, 2, 0.5), InputError);
  EXPECT_THROW(cascadeSplits(1.0, 100.0, 0, 0.5), InputError);
  EXPECT_THROW(cascadeSplits(1.0, 100.0, kMaxCascades + 1, 0.5), InputError);
  EXPECT_THROW(cascadeSplits(1.0, 100.0, 2, -0.1), InputError);
  EXPECT_THROW(cascadeSplits(1.0, 100.0, 2, nan), InputError);
  try {
    cascadeSplits(1.0, 100.0, 5, 0.5);
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("5 cascades: expected 1 to 4"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace forest::shadows
