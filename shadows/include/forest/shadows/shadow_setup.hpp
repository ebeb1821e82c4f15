#pragma once
// Light view-projection for a directional light (the sun), by method:
//   uniform        — orthographic map fitted to the focus body B in the light frame L;
//   uniform-stable — orthographic, orientation fixed in the world, size from V's bounding sphere,
//                    origin snapped to whole texels: shadows do not swim when the camera turns;
//   lispsm         — light space perspective shadow map, thesis §9.2 step by step.
// Output: a world → [−1, 1]³ matrix (x, y: shadow-map plane, z: depth increasing away from the
// light), composed in double and also given in float32 for the GPU, plus diagnostics.
#include <glm/glm.hpp>

#include <optional>
#include <string>
#include <string_view>

#include "forest/core/bounds.hpp"
#include "forest/core/camera.hpp"
#include "forest/core/convex_body.hpp"

namespace forest::shadows {

enum class ShadowMethod { Uniform, UniformStable, Lispsm };
ShadowMethod parseShadowMethod(std::string_view name);  // throws InputError
std::string_view shadowMethodName(ShadowMethod method);

// Past n > kLispsmCapFactor · d the warp is gone (thesis §8.3: LiSPSM converges to uniform as
// γ → 0); the warp strength 1/n fades linearly to 0 at the cap, so there is no jump.
constexpr double kLispsmCapFactor = 1e3;
constexpr int kMaxMapSize = 16384;  // texels per side; larger maps are refused (DESIGN §7)
constexpr double kFloatUnitRoundoff = 0x1p-24;  // u of IEEE binary32

struct ShadowInput {
  Camera camera;
  glm::dvec3 sunDirection{0.0, -1.0, 0.0};  // the way light travels; need not be unit
  Aabb scene;                               // S
  std::optional<Aabb> receivers;            // bounds of the visible receivers (tighter B)
  std::optional<double> nFar;               // (smoothed) far distance of the visible set, for n only (§9.2.5)
  int mapSize = 2048;                       // texels per side
  int borderTexels = 2;                     // kept free around B for the PCF and blur footprint
};

struct ShadowDiagnostics {
  double n = 0.0;          // LiSPSM near distance (eq. 8.13), clamped to the cap; 0 for uniform
  double nCap = 0.0;       // kLispsmCapFactor × B's depth along the warp axis (lispsm)
  double warp = 0.0;       // 1/n actually used after the fade (0 = no warp)
  double gammaDeg = 0.0;   // angle between the body vector and the light direction
  double z0 = 0.0;         // eye-space z of z0_ls and z1_ls (§9.2.5), negative in front
  double z1 = 0.0;
  double d = 0.0;          // light-space depth extent of B along the warp axis
  size_t bodyVertices = 0;
  std::string fallback;    // "" or why the method fell back ("empty focus body", "n at cap", ...)
  double floatShrink = 0.0;  // share of the map given up to keep B inside it in float32 (usually 0)
};

struct ShadowSetup {
  glm::dmat4 worldToShadowClip{1.0};  // world → [−1, 1]³
  glm::mat4 worldToShadowClipF{1.0};  // the same in float32 (imprecise far from the origin)
  // (p − eye) → [−1, 1]³ in float32: what the GPU gets, with camera-relative positions, so that
  // precision does not depend on where in the world the camera is (DESIGN §4).
  glm::mat4 eyeRelativeToShadowClipF{1.0};
  ConvexBody body;                    // B
  bool empty = true;                  // nothing visible to shadow
  ShadowDiagnostics diagnostics;
};

// Validates the input (throws InputError: zero or non-finite sun, near ≥ far, ...).
void validateShadowInput(const ShadowInput& input);
ShadowSetup computeShadowSetup(const ShadowInput& input, ShadowMethod method);

// Upper bound on |x|, |y|, |z| of the shadow-clip coordinates the GPU computes for a
// camera-relative position (rounded to float32) with the float32 matrix, whatever the order of
// its float operations: the exact result plus the rounding bound. +∞ when w may be ≤ 0.
glm::dvec3 mapCoordinateBound(const glm::mat4& eyeRelativeToShadowClip, const glm::dvec3& eyeRelativePosition);

// Eq. 8.13 with the misprint fixed (DESIGN §4): n = d / (√(z1/z0) − 1); z0, z1 negative eye-space
// depths, |z1| > |z0|. Returns +∞ when z1/z0 ≤ 1.
double lispsmNearDistance(double d, double z0, double z1);

}  // namespace forest::shadows
