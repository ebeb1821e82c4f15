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
