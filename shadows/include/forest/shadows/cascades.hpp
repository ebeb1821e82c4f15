#pragma once
// Z-partitioning of the view's depth range for cascaded shadow maps (issue "Z-partitioned
// shadows"; DESIGN §4): the practical split scheme of Zhang et al., "Parallel-Split Shadow Maps
// for Large-scale Virtual Environments" (VRCIA 2006), eq. (4) — a blend, by λ, of the logarithmic
// split (optimal for perspective aliasing, thesis §8.2 eq. 8.4) and the uniform one.
#include <vector>

namespace forest::shadows {

constexpr int kMaxCascades = 4;

// The K + 1 split depths z_0 = near < z_1 < … < z_K = far of [near, far] into K slices:
//   z_i = λ · near · (far / near)^(i/K) + (1 − λ) · (near + (far − near) · i / K),
// with z_0 and z_K exactly near and far (no gap at either end, whatever the rounding). Throws
// InputError unless 0 < near < far (finite), 1 ≤ K ≤ kMaxCascades and λ in [0, 1].
std::vector<double> cascadeSplits(double near, double far, int cascades, double lambda);

}  // namespace forest::shadows
