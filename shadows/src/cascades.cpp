#include "forest/shadows/cascades.hpp"

#include <fmt/format.h>

#include <cmath>

#include "forest/core/error.hpp"

namespace forest::shadows {

std::vector<double> cascadeSplits(double near, double far, int cascades, double lambda) {
  if (!(std::isfinite(near) && std::isfinite(far) && near > 0.0 && far > near))
    throw InputError(fmt::format("cascade splits: near {} and far {}: expected 0 < near < far, both finite", near, far));
  if (cascades < 1 || cascades > kMaxCascades)
    throw InputError(fmt::format("cascade splits: {} cascades: expected 1 to {}", cascades, kMaxCascades));
  if (!(lambda >= 0.0 && lambda <= 1.0)) throw InputError(fmt::format("cascade splits: λ = {}: expected [0, 1]", lambda));
  std::vector<double> splits(static_cast<size_t>(cascades) + 1);
  splits.front() = near;
  splits.back() = far;
  for (int i = 1; i < cascades; ++i) {  // Zhang et al. 2006, eq. (4)
    const double t = static_cast<double>(i) / cascades;
    const double logarithmic = near * std::pow(far / near, t), uniform = near + (far - near) * t;
    splits[static_cast<size_t>(i)] = lambda * logarithmic + (1.0 - lambda) * uniform;
  }
  return splits;
}

}  // namespace forest::shadows
