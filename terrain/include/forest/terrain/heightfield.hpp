#pragma once
// The procedural heightfield (DESIGN §4 terrain/): a square grid of float32 heights from seeded
// fBm blended with ridged multifractal noise. Same settings → bit-identical heights (only + × and
// floor in double, every sample independent of thread scheduling).
#include <glm/glm.hpp>

#include <vector>

#include "forest/core/scene.hpp"

namespace forest::terrain {

class Heightfield {
 public:
  // Generates the heights (several threads; logs progress for large grids). Settings must be
  // valid (the scene loader checks them); throws InputError otherwise.
  explicit Heightfield(const TerrainSettings& settings);

  int samples() const { return samples_; }          // per side
  double size() const { return size_; }             // metres per side
  double spacing() const { return spacing_; }       // metres between samples
  glm::dvec2 origin() const { return origin_; }     // world (x, z) of sample (0, 0)
  // Height of sample (i, j): i along x, j along z.
  float at(int i, int j) const { return heights_[static_cast<size_t>(j) * samples_ + i]; }
  const std::vector<float>& heights() const { return heights_; }
  // World position of sample (i, j).
  glm::dvec3 position(int i, int j) const {
    return {origin_.x + i * spacing_, static_cast<double>(at(i, j)), origin_.y + j * spacing_};
  }
  // Unit normal at sample (i, j) from central differences (one-sided at the border); the vertex
  // normal the drawn mesh interpolates.
  glm::dvec3 sampleNormal(int i, int j) const;

 private:
  int samples_ = 0;
  double size_ = 0.0, spacing_ = 0.0;
  glm::dvec2 origin_{0.0};
  std::vector<float> heights_;
};

// Seeded 2D gradient noise (Perlin's improved noise, 2D), about [−1, 1], exactly 0 at integer
// lattice points. Deterministic across runs and platforms with IEEE doubles.
class GradientNoise {
 public:
  explicit GradientNoise(std::uint64_t seed);
  double operator()(double x, double z) const;

 private:
  int permutation_[512];
};

}  // namespace forest::terrain
