#pragma once
// The passes of a frame, in the order they run (DESIGN §1), and their names: the one table the
// pass timer, the frame's statistics, report.json, budget files and the apps all use.
#include <array>
#include <cstddef>
#include <numeric>

#include "forest/core/enum_names.hpp"

namespace forest {

enum class FramePass { Geometry, ShadowSetup, Shadow, ShadowTerm, Blur, Lighting };
inline constexpr std::size_t kFramePassCount = 6;
inline constexpr EnumNames<FramePass, kFramePassCount> kFramePassNames{
    "frame pass", {{{FramePass::Geometry, "geometry"}, {FramePass::ShadowSetup, "shadow_setup"}, {FramePass::Shadow, "shadow"},
                    {FramePass::ShadowTerm, "shadow_term"}, {FramePass::Blur, "blur"}, {FramePass::Lighting, "lighting"}}}};

// Milliseconds per pass.
struct PassTimes {
  std::array<double, kFramePassCount> ms{};
  double& operator[](FramePass pass) { return ms[static_cast<std::size_t>(pass)]; }
  double operator[](FramePass pass) const { return ms[static_cast<std::size_t>(pass)]; }
  double total() const { return std::accumulate(ms.begin(), ms.end(), 0.0); }
};

}  // namespace forest
