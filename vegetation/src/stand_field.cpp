#include "forest/vegetation/stand_field.hpp"

#include <algorithm>
#include <vector>

namespace forest::vegetation {

StandField::StandField(const StandSettings& settings, std::uint64_t seed, const glm::dvec2& areaMin, const glm::dvec2& areaMax)
    : settings_(settings), gradient_(seed ^ 0x57a2d5ull) {
  // τ: the (1 − cover)-quantile of g over the area, so that g ≥ τ (D ≥ 1/2) on `cover` of it.
  std::vector<double> samples;
  samples.reserve(static_cast<size_t>(kSamplesPerSide) * kSamplesPerSide);
  for (int j = 0; j < kSamplesPerSide; ++j)
    for (int i = 0; i < kSamplesPerSide; ++i) {
      const glm::dvec2 t((i + 0.5) / kSamplesPerSide, (j + 0.5) / kSamplesPerSide);
      const glm::dvec2 p = areaMin + t * (areaMax - areaMin);
      samples.push_back(noise(p.x, p.y));
    }
  std::vector<double> sorted = samples;
  std::sort(sorted.begin(), sorted.end());
  const auto at = [&](double q) {
    return sorted[std::min(sorted.size() - 1, static_cast<size_t>(q * static_cast<double>(sorted.size())))];
  };
  threshold_ = at(1.0 - settings.cover);
  // w: `edge` of the spread between g's 5th and 95th percentiles.
  halfWidth_ = 0.5 * settings.edge * std::max(at(0.95) - at(0.05), 1e-9);
  size_t inside = 0;
  for (double g : samples) inside += g >= threshold_ ? 1 : 0;
  standShare_ = static_cast<double>(inside) / static_cast<double>(samples.size());
}

double StandField::noise(double x, double z) const {
  double sum = 0.0, amplitude = 1.0, norm = 0.0, frequency = 1.0 / settings_.feature_m;
  for (int octave = 0; octave < 3; ++octave) {
    sum += amplitude * gradient_(x * frequency + 17.3 * octave, z * frequency - 9.1 * octave);
    norm += amplitude;
    amplitude *= 0.5;
    frequency *= 2.0;
  }
  return sum / norm;
}

double StandField::density(double x, double z) const {
  const double t = std::clamp((noise(x, z) - (threshold_ - halfWidth_)) / (2.0 * halfWidth_), 0.0, 1.0);
  const double ramp = t * t * (3.0 - 2.0 * t);  // smoothstep
  return settings_.meadow + (1.0 - settings_.meadow) * ramp;
}

std::vector<float> StandField::densityGrid(int side, const glm::dvec2& areaMin, const glm::dvec2& areaMax) const {
  std::vector<float> grid;
  grid.reserve(static_cast<size_t>(side) * side);
  for (int j = 0; j < side; ++j)
    for (int i = 0; i < side; ++i) {
      const glm::dvec2 p = areaMin + glm::dvec2((i + 0.5) / side, (j + 0.5) / side) * (areaMax - areaMin);
      grid.push_back(static_cast<float>(density(p.x, p.y)));
    }
  return grid;
}

}  // namespace forest::vegetation
