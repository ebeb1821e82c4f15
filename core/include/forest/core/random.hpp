#pragma once
// The engine's one random stream: SplitMix64 (Steele, Lea & Flood, "Fast splittable pseudorandom
// number generators", OOPSLA 2014). Fixed arithmetic, so a seed gives the same numbers on every
// platform and standard library (std:: distributions do not promise that).
#include <cmath>
#include <cstdint>

namespace forest {

class SplitMix64 {
 public:
  explicit SplitMix64(std::uint64_t seed) : state_(seed) {}

  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  // Uniform in [0, 1), 53 random bits.
  double unit() { return static_cast<double>(next() >> 11) * 0x1p-53; }
  double uniform(double a, double b) { return a + (b - a) * unit(); }
  double logUniform(double a, double b) { return std::exp(uniform(std::log(a), std::log(b))); }
  bool chance(double p) { return unit() < p; }

  // A seed for substream `index` of `seed` (a fresh generator per case, tree, ...).
  static std::uint64_t substream(std::uint64_t seed, std::uint64_t index) { return seed * 0x9e3779b97f4a7c15ull + index; }

 private:
  std::uint64_t state_;
};

}  // namespace forest
