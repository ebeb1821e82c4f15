#include "forest/terrain/heightfield.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <numeric>

#include "forest/core/error.hpp"
#include "forest/core/log.hpp"
#include "forest/core/parallel.hpp"
#include "forest/core/random.hpp"

namespace forest::terrain {
namespace {

// Ridged noise takes 1 − |n|; |n| is rounded to √(n² + r²) so ridge crests are smooth at the
// sample spacing instead of cusps (cusps make every LOD level's error large; thesis-scale
// terrain has no knife edges at 2 m).
constexpr double kRidgeRounding = 0.1;

double fade(double t) { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); }  // 6t⁵ − 15t⁴ + 10t³

double gradient(int hash, double x, double z) {
  switch (hash & 7) {
    case 0: return x + z;
    case 1: return -x + z;
    case 2: return x - z;
    case 3: return -x - z;
    case 4: return x;
    case 5: return -x;
    case 6: return z;
    default: return -z;
  }
}

void validate(const TerrainSettings& s) {
  if (!(s.size >= 64.0 && s.size <= 65536.0)) throw InputError(fmt::format("terrain.size = {}: expected [64, 65536] m", s.size));
  if (s.samples < 65 || s.samples > 8193 || (s.samples - 1) % 64 != 0)
    throw InputError(fmt::format("terrain.samples = {}: expected 65…8193 with samples − 1 a multiple of 64", s.samples));
  if (!(s.height_max > s.height_min)) throw InputError("terrain.height_max: must be greater than terrain.height_min");
  if (!(s.feature_size > 0.0) || !std::isfinite(s.feature_size)) throw InputError("terrain.feature_size: expected > 0");
  if (s.octaves < 1 || s.octaves > 16) throw InputError(fmt::format("terrain.octaves = {}: expected [1, 16]", s.octaves));
  if (!(s.ridged >= 0.0 && s.ridged <= 1.0)) throw InputError(fmt::format("terrain.ridged = {}: expected [0, 1]", s.ridged));
}

}  // namespace

GradientNoise::GradientNoise(std::uint64_t seed) {
  SplitMix64 random(seed);
  std::iota(permutation_, permutation_ + 256, 0);
  for (int i = 255; i > 0; --i) std::swap(permutation_[i], permutation_[random.next() % static_cast<std::uint64_t>(i + 1)]);
  std::copy(permutation_, permutation_ + 256, permutation_ + 256);
}

double GradientNoise::operator()(double x, double z) const {
  const double fx = std::floor(x), fz = std::floor(z);
  const int xi = static_cast<int>(static_cast<std::int64_t>(fx) & 255), zi = static_cast<int>(static_cast<std::int64_t>(fz) & 255);
  const double dx = x - fx, dz = z - fz;
  const double u = fade(dx), v = fade(dz);
  const int a = permutation_[xi] + zi, b = permutation_[xi + 1] + zi;
  const double n00 = gradient(permutation_[a], dx, dz), n10 = gradient(permutation_[b], dx - 1.0, dz);
  const double n01 = gradient(permutation_[a + 1], dx, dz - 1.0), n11 = gradient(permutation_[b + 1], dx - 1.0, dz - 1.0);
  const double x0 = n00 + u * (n10 - n00), x1 = n01 + u * (n11 - n01);
  return 0.5 * (x0 + v * (x1 - x0));  // the 2D gradients reach ±2: scale to about [−1, 1]
}

Heightfield::Heightfield(const TerrainSettings& settings) {
  validate(settings);
  samples_ = settings.samples;
  size_ = settings.size;
  spacing_ = size_ / (samples_ - 1);
  origin_ = glm::dvec2(-0.5 * size_);
  heights_.resize(static_cast<size_t>(samples_) * samples_);

  const GradientNoise noise(settings.seed);
  // Per-octave offsets from the seed keep octaves from sharing lattice points at the origin.
  SplitMix64 random(settings.seed ^ 0x5eedf00dull);
  std::vector<glm::dvec2> offsets(static_cast<size_t>(settings.octaves));
  for (glm::dvec2& o : offsets) {
    o.x = static_cast<double>(random.next() >> 40) / 65536.0;
    o.y = static_cast<double>(random.next() >> 40) / 65536.0;
  }
  // Raw height at world (x, z): fBm (gain 1/2) blended with Musgrave's ridged multifractal
  // (signal (1 − |n|)², weighted by the previous octave's signal).
  auto raw = [&](double x, double z) {
    double fbm = 0.0, ridged = 0.0, amplitude = 1.0, frequency = 1.0 / settings.feature_size, weight = 1.0;
    for (int o = 0; o < settings.octaves; ++o) {
      const double n = noise(x * frequency + offsets[o].x, z * frequency + offsets[o].y);
      fbm += amplitude * n;
      double signal = 1.0 - std::sqrt(n * n + kRidgeRounding * kRidgeRounding);
      signal *= signal * weight;
      weight = std::clamp(2.0 * signal, 0.0, 1.0);
      ridged += amplitude * signal;
      amplitude *= 0.5;
      frequency *= 2.0;
    }
    return (1.0 - settings.ridged) * fbm + settings.ridged * (2.0 * ridged - 1.0);
  };

  std::atomic<int> rowsDone{0};
  const bool large = samples_ > 2049;
  parallelFor(samples_, [&](int j) {
    for (int i = 0; i < samples_; ++i)
      heights_[static_cast<size_t>(j) * samples_ + i] = static_cast<float>(raw(origin_.x + i * spacing_, origin_.y + j * spacing_));
    const int done = ++rowsDone;  // the row that completes a quarter reports it, once
    if (large && 4 * done / samples_ > 4 * (done - 1) / samples_ && 4 * done / samples_ < 4)
      log::info("terrain: {}% of {}x{} heights", 25 * (4 * done / samples_), samples_, samples_);
  });
  if (large) log::info("terrain: {}x{} heights done", samples_, samples_);

  // Rescale to fill [height_min, height_max] exactly.
  const auto [lo, hi] = std::minmax_element(heights_.begin(), heights_.end());
  const double rawMin = *lo, rawMax = *hi;
  const double scale = rawMax > rawMin ? (settings.height_max - settings.height_min) / (rawMax - rawMin) : 0.0;
  for (float& h : heights_) h = static_cast<float>(settings.height_min + (h - rawMin) * scale);
  // The extremes land exactly on the range ends.
  *lo = static_cast<float>(settings.height_min);
  if (scale > 0.0) *hi = static_cast<float>(settings.height_max);
}

glm::dvec3 Heightfield::sampleNormal(int i, int j) const {
  const int i0 = std::max(i - 1, 0), i1 = std::min(i + 1, samples_ - 1);
  const int j0 = std::max(j - 1, 0), j1 = std::min(j + 1, samples_ - 1);
  const double dhdx = (static_cast<double>(at(i1, j)) - at(i0, j)) / ((i1 - i0) * spacing_);
  const double dhdz = (static_cast<double>(at(i, j1)) - at(i, j0)) / ((j1 - j0) * spacing_);
  return glm::normalize(glm::dvec3(-dhdx, 1.0, -dhdz));
}

}  // namespace forest::terrain
