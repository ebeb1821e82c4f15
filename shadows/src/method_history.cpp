#include "forest/shadows/method_history.hpp"

#include <fmt/format.h>

#include "forest/core/error.hpp"

namespace forest::shadows {
namespace {

std::size_t sliceIndex(int slice) {
  if (slice < 0 || slice >= kMaxCascades) throw InputError(fmt::format("shadow slice {}: expected 0 to {}", slice, kMaxCascades - 1));
  return static_cast<std::size_t>(slice);
}

}  // namespace

double MethodHistory::carried(ShadowMethod method, int slice) const {
  const std::size_t s = sliceIndex(slice);
  return by_[s] == method ? carried_[s] : 0.0;
}

void MethodHistory::remember(ShadowMethod method, int slice, const ShadowSetup& setup) {
  const std::size_t s = sliceIndex(slice);
  carried_[s] = carriedToNextFrame(method, setup);
  by_[s] = method;
}

void MethodHistory::reset() {
  carried_.fill(0.0);
  by_.fill(std::nullopt);
}

}  // namespace forest::shadows
