#pragma once
// The stability suite (DESIGN §6): shadow setups on hard and random configurations, and the
// invariants every setup must keep with the float32 matrix the GPU gets.
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "forest/shadows/shadow_setup.hpp"

namespace forest::shadows {

struct StabilityCase {
  std::string name;
  ShadowInput input;
};

// A JSON array of cases (or an object with a "cases" array). Each case has
//   name, eye [x,y,z], view_dir, up, fovy_deg, aspect, near, far, sun_dir, scene_min, scene_max
// and optionally receivers [{"min": [..], "max": [..]}, ...] (their union bounds B), n_far,
// map_size, border_texels. sun_dir is the way light travels (noon is [0, -1, 0]).
// Throws InputError naming the source, the case and the field: "cases.json: case 3 ('low sun'):
// near: expected a number > 0, got -1".
std::vector<StabilityCase> parseStabilityCases(std::string_view json, const std::string& source);
std::vector<StabilityCase> loadStabilityCases(const std::filesystem::path& file);

// Configuration `index` of the random stream `seed`: the same pair always gives the same case,
// so a failure found in a million is reproduced alone. Covers the ranges of DESIGN §6: any view
// and sun direction (grazing and parallel ones included), near 1e-4…1 with far up to 1e6·near,
// fov 0.5°…170°, aspect 0.1…10, flat and thin scene boxes, cameras far from the origin and
// outside the scene, optional receiver boxes.
StabilityCase randomStabilityCase(std::uint64_t seed, std::uint64_t index);

struct InvariantCheck {
  std::string name;  // "finite", "body in map", "visible in map", "n valid"
  bool passed = true;
  std::string detail;  // why it failed
};

struct StabilityReport {
  std::vector<InvariantCheck> checks;
  double maxMapCoordinate = 0.0;  // largest |x|, |y|, |z| of B's vertices on the float32 path
  bool passed() const;
};

// The invariants of one setup (issue "Shadow math I"), evaluated as the GPU does: float32
// eye-relative matrix, float32 camera-relative positions, float32 arithmetic.
//  - finite: every float32 matrix entry finite;
//  - body in map: every vertex of B inside [−1, 1]³ (w > 0), no tolerance;
//  - visible in map: every vertex of V ∩ S (V ∩ receivers) inside the map's x, y range;
//  - n valid (lispsm): 0 < n ≤ cap, finite; warp 1/n ≥ 0.
StabilityReport checkSetupInvariants(const ShadowInput& input, ShadowMethod method, const ShadowSetup& setup);

}  // namespace forest::shadows
