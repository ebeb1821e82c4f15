#pragma once
// Z-partitioning of the view's depth range for cascaded shadow maps (issue "Z-partitioned
// shadows"; DESIGN §4): the practical split scheme of Zhang et al., "Parallel-Split Shadow Maps
// for Large-scale Virtual Environments" (VRCIA 2006), eq. (4) — a blend, by λ, of the logarithmic
// split (optimal for perspective aliasing, thesis §8.2 eq. 8.4) and the uniform one.
#include <array>
#include <cstddef>
#include <vector>

#include "forest/core/camera.hpp"
#include "forest/shadows/shadow_setup.hpp"

namespace forest::shadows {

constexpr int kMaxCascades = 4;

// K + 1 split depths in a fixed array (a frame computes them without allocating, DESIGN §9).
struct SplitDepths {
  std::array<double, kMaxCascades + 1> z{};
  int cascades = 0;  // K
  std::size_t size() const { return static_cast<std::size_t>(cascades) + 1; }
  double operator[](std::size_t i) const { return z[i]; }
  double& operator[](std::size_t i) { return z[i]; }
  double front() const { return z[0]; }
  double back() const { return z[static_cast<std::size_t>(cascades)]; }
};

// The K + 1 split depths z_0 = near < z_1 < … < z_K = far of [near, far] into K slices:
//   z_i = λ · near · (far / near)^(i/K) + (1 − λ) · (near + (far − near) · i / K),
// with z_0 and z_K exactly near and far (no gap at either end, whatever the rounding). Throws
// InputError unless 0 < near < far (finite), 1 ≤ K ≤ kMaxCascades and λ in [0, 1].
SplitDepths cascadeSplits(double near, double far, int cascades, double lambda);

// The splits over time (DESIGN §12): each inner split of `target` moves from `previous`'s
// (the last frame's, same K; else none) kNearDistanceSmoothing of the way in log depth,
//   z_i ← exp(ln z_i' + 0.2 · (ln z_i − ln z_i')),
// so that a jump of z_f or z_near does not move every slice's texels at once. A smoothed split
// that would not lie above the (smoothed) split below it, or not below z_K, takes the target's
// value; a split that is then still not above the one below goes halfway from that one to z_K, so
// that no slice is empty. z_0 and z_K are the target's.
SplitDepths smoothSplits(const SplitDepths& target, const SplitDepths& previous);

// A slice's focus body reaches this share beyond its ends, past any blend band: the shadow lookup
// picks the slice by an eye depth it reconstructs in float32 from the depth buffer (relative error
// ~10⁻⁶), so a pixel at a split reads a layer whose B holds it either way.
constexpr double kSliceOverlap = 1e-3;

// The eye camera whose view is slice `slice` of `splits` (splits[0]: the camera's near plane,
// splits[K]: the far end): near at the split before it (less kSliceOverlap), far at the split after
// it plus the blend band — the share `blend` of the split's distance over which the shader fades
// this slice into the next — or kSliceOverlap, whichever is larger; the last slice ends at splits[K].
Camera sliceCamera(const Camera& camera, const SplitDepths& splits, int slice, double blend);

// The stability suite's view of z-partitioning (DESIGN §6): the input's view [near, far] split by
// eq. (4) into K slices, each an input of its own (the slice's camera, the same sun, scene and
// receivers; no nFar), whose setup must keep every invariant on its own.
std::vector<ShadowInput> cascadeInputs(const ShadowInput& input, int cascades, double lambda, double blend);

}  // namespace forest::shadows
