#include "forest/shadows/cascades.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "forest/core/error.hpp"

namespace forest::shadows {

SplitDepths cascadeSplits(double near, double far, int cascades, double lambda) {
  if (!(std::isfinite(near) && std::isfinite(far) && near > 0.0 && far > near))
    throw InputError(fmt::format("cascade splits: near {} and far {}: expected 0 < near < far, both finite", near, far));
  if (cascades < 1 || cascades > kMaxCascades)
    throw InputError(fmt::format("cascade splits: {} cascades: expected 1 to {}", cascades, kMaxCascades));
  if (!(lambda >= 0.0 && lambda <= 1.0)) throw InputError(fmt::format("cascade splits: λ = {}: expected [0, 1]", lambda));
  SplitDepths splits;
  splits.cascades = cascades;
  splits[0] = near;
  splits[static_cast<size_t>(cascades)] = far;
  for (int i = 1; i < cascades; ++i) {  // Zhang et al. 2006, eq. (4)
    const double t = static_cast<double>(i) / cascades;
    const double logarithmic = near * std::pow(far / near, t), uniform = near + (far - near) * t;
    splits[static_cast<size_t>(i)] = lambda * logarithmic + (1.0 - lambda) * uniform;
  }
  return splits;
}

SplitDepths smoothSplits(const SplitDepths& target, const SplitDepths& previous) {
  SplitDepths splits = target;
  const int k = target.cascades;
  const double farDepth = target.back();
  if (previous.cascades == k)
    for (int i = 1; i < k; ++i) {
      const size_t s = static_cast<size_t>(i);
      const double last = std::log(previous[s]);
      const double smoothed = std::exp(last + kNearDistanceSmoothing * (std::log(target[s]) - last));
      if (smoothed > splits[s - 1] && smoothed < farDepth) splits[s] = smoothed;
    }
  for (size_t s = 1; s < static_cast<size_t>(k); ++s)  // the order, whatever the smoothing kept
    if (!(splits[s] > splits[s - 1])) splits[s] = 0.5 * (splits[s - 1] + farDepth);
  return splits;
}

Camera sliceCamera(const Camera& camera, const SplitDepths& splits, int slice, double blend) {
  const size_t i = static_cast<size_t>(slice);
  Camera c = camera;
  c.near = slice == 0 ? splits[0] : splits[i] * (1.0 - kSliceOverlap);
  c.far = slice + 1 == splits.cascades ? splits.back() : std::min(splits.back(), splits[i + 1] * (1.0 + std::max(blend, kSliceOverlap)));
  return c;
}

std::vector<ShadowInput> cascadeInputs(const ShadowInput& input, int cascades, double lambda, double blend) {
  const SplitDepths splits = cascadeSplits(input.camera.near, input.camera.far, cascades, lambda);
  std::vector<ShadowInput> slices;
  for (int i = 0; i < cascades; ++i) {
    ShadowInput slice = input;
    slice.camera = sliceCamera(input.camera, splits, i, blend);
    slice.nFar.reset();
    slices.push_back(slice);
  }
  return slices;
}

}  // namespace forest::shadows
