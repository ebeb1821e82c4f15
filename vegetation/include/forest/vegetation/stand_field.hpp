#pragma once
// The forest's density field D(x, z) in [meadow, 1] ([vegetation.stands], docs/scene-format.md):
// stands where D = 1, clearings and meadows where D falls to the meadow's value, soft edges
// between. D = meadow + (1 − meadow) · smoothstep(τ − w, τ + w, g(x, z)), with g a seeded fBm of
// gradient noise (3 octaves, wavelength feature_m), τ its (1 − cover)-quantile over the terrain —
// so the stands (g ≥ τ, the middle of the edge ramp) cover `cover` of it — and w = ½ edge × the
// spread of g (its 5th to 95th percentile). Dart throwing keeps a dart with probability D
// (vegetation/forest.cpp).
#include <cstdint>
#include <vector>

#include "forest/core/bounds.hpp"
#include "forest/core/scene.hpp"
#include "forest/terrain/heightfield.hpp"

namespace forest::vegetation {

class StandField {
 public:
  // `area`: the terrain's (x, z) extent, where the quantile is taken (a 256² sample grid).
  StandField(const StandSettings& settings, std::uint64_t seed, const glm::dvec2& areaMin, const glm::dvec2& areaMax);

  double density(double x, double z) const;  // D, in [meadow, 1]
  // D at the centres of side × side cells over [areaMin, areaMax], row by row (+x first, then +z):
  // the ground cover the terrain's material reads (render/terrain_renderer.hpp).
  std::vector<float> densityGrid(int side, const glm::dvec2& areaMin, const glm::dvec2& areaMax) const;
  bool inStand(double x, double z) const { return noise(x, z) >= threshold_; }
  // The share of the area in stands, from the same sample grid as the quantile.
  double standShare() const { return standShare_; }

  static constexpr int kSamplesPerSide = 256;

 private:
  double noise(double x, double z) const;  // g: fBm, about [−1, 1]

  StandSettings settings_;
  terrain::GradientNoise gradient_;
  double threshold_ = 0.0;  // τ
  double halfWidth_ = 0.0;  // w
  double standShare_ = 0.0;
};

}  // namespace forest::vegetation
