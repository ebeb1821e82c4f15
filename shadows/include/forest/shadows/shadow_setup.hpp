#pragma once
// Light view-projection for a directional light (the sun), by method:
//   uniform        — orthographic map fitted to the focus body B in the light frame L;
//   uniform-stable — orthographic, orientation fixed in the world, size from V's bounding sphere,
//                    origin snapped to whole texels: shadows do not swim when the camera turns;
//   lispsm         — light space perspective shadow map, thesis §9.2 step by step;
//   tsm            — trapezoidal shadow map (Martin & Tan 2004, §6): the uniform map's plane warped
//                    so that a trapezoid around B's footprint fills it, 80% rule for the focus
//                    region; depth stays the uniform map's linear light depth (TSM §4);
//   tsm-iterative  — the same with the iterative variant of §6.2 (the focus line that gives the
//                    focus region the largest area in the map).
// Output: a world → [−1, 1]³ matrix (x, y: shadow-map plane, z: depth increasing away from the
// light), composed in double and also given in float32 for the GPU, plus diagnostics.
#include <glm/glm.hpp>

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "forest/core/bounds.hpp"
#include "forest/core/camera.hpp"
#include "forest/core/enum_names.hpp"
#include "forest/core/convex_body.hpp"

namespace forest::shadows {

enum class ShadowMethod { Uniform, UniformStable, Lispsm, Tsm, TsmIterative };
inline constexpr EnumNames<ShadowMethod, 5> kShadowMethodNames{
    "shadow method", {{{ShadowMethod::Uniform, "uniform"}, {ShadowMethod::UniformStable, "uniform-stable"},
                       {ShadowMethod::Lispsm, "lispsm"}, {ShadowMethod::Tsm, "tsm"}, {ShadowMethod::TsmIterative, "tsm-iterative"}}}};

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
  // A far distance for n only (§9.2.5): n is computed on the body of the camera with this far
  // instead (stability case files; the frame smooths n itself, see previousN).
  std::optional<double> nFar;
  // A near distance for n only (cascades; Lauritzen et al. 2011): the nearest depth anything
  // visible lies at. n is computed on the body of the camera with this near instead (with nFar
  // when given), so the warp is not spent between the near plane and the first visible surface;
  // B and the map still start at the camera's near. Ignored unless near < nNear < far (and nFar).
  std::optional<double> nNear;
  // What this method's setup of the same slice carried from the last frame (MethodHistory;
  // lispsm: its n, which then moves kNearDistanceSmoothing of the way to this frame's eq. 8.13
  // value; uniform-stable: its map radius, kept while it still fits the view, stableMapRadius).
  // 0: nothing (the first frame, after a cut).
  double carried = 0.0;
  int mapSize = 2048;                       // texels per side
  int borderTexels = 2;                     // kept free around B for the PCF and blur footprint
  // tsm: the focus region is the first focusShare of the visible depth range (TSM §6.2 and §6.4:
  // δ = focusShare · f, scaled to the part of the frustum inside S). A choice, not from the paper.
  double tsmFocusShare = 0.3;
  // A kept slice's refit (kept_slices.hpp): the warp's parameters on lattices, so that the refits
  // of a slowly moving camera land on the same map as often as possible — the light frame's
  // rotation about the light in steps of kWarpRotationStepDeg, lispsm's n on steps of 2^(1/4)
  // (eq. 8.13's value rounded, not smoothed: `carried` is ignored).
  bool snapWarp = false;
  // Points the map must hold besides B (a kept slice's refit: the focus body of the camera a few
  // frames ahead). They widen the fit, not B, n or the body vector. Not owned.
  std::span<const glm::dvec3> alsoCover;
};

// snapWarp's lattices: the body vector's azimuth about the light (§9.2.6; it turns the light frame
// L, §9.2.3) in steps of this many degrees (half a step off the optimum at most), lispsm's n in
// steps of 2^kWarpNStep (at most 9% off eq. 8.13's value).
constexpr double kWarpRotationStepDeg = 2.0;
constexpr double kWarpNStep = 0.25;

// TSM §6.2: the 80% line. The focus point goes to y = ξ of the map's [−1, 1] (80% of its height
// from the top line at +1).
constexpr double kTsmFocusLine = -0.6;

// TSM §6.2, the 1D perspective projection: the distance η of the projection centre q beyond the
// top line that maps the top line to +1, the base line (λ away) to −1 and the focus point (δ'
// below the top line) to ξ:  η = λδ'(1 + ξ) / (λ − 2δ' − λξ). +∞ when no finite q does it.
double tsmProjectionDistance(double lambda, double deltaPrime, double xi);

// §9.2.5 warns that the visible set's z_f jumps when objects appear or vanish, and n with it; the
// thesis smooths z_f. Here B is also bounded by the visible receivers, which jump together with
// z_f, so the smoothing is applied to n itself: each frame n moves this share of the way to the
// new eq. 8.13 value, in both directions (a jump is spread over ~10 frames: 0.8¹⁰ ≈ 0.11 left).
constexpr double kNearDistanceSmoothing = 0.2;

struct ShadowDiagnostics {
  double n = 0.0;          // LiSPSM near distance used: eq. 8.13 (smoothed over time), clamped to the cap; 0 for uniform
  double nOptimal = 0.0;   // eq. 8.13 on this frame's B, clamped to the cap, before the smoothing
  double nCap = 0.0;       // kLispsmCapFactor × B's depth along the warp axis (lispsm)
  double warp = 0.0;       // 1/n actually used after the fade (0 = no warp)
  double gammaDeg = 0.0;   // angle between the body vector and the light direction
  double z0 = 0.0;         // eye-space z of z0_ls and z1_ls (§9.2.5), negative in front
  double z1 = 0.0;
  double d = 0.0;          // light-space depth extent of B along the warp axis
  size_t bodyVertices = 0;
  // "" or why the method fell back ("empty focus body", "n at cap: uniform", ...): a static note,
  // so that a frame that falls back allocates nothing (DESIGN §9).
  std::string_view fallback;
  double stableRadius = 0.0;  // uniform-stable: the radius (m) the map covers (stableMapRadius)
  double floatShrink = 0.0;  // share of the map given up to keep B inside it in float32 (usually 0)
  // tsm (§6): λ (top to base line), δ' (focus point below the top line), both in the uniform
  // map's [−1, 1] units; η actually used; ξ the focus line; the focus region's share of the map.
  double tsmLambda = 0.0, tsmFocus = 0.0, tsmEta = 0.0, tsmXi = 0.0, tsmFocusArea = 0.0;
};

struct ShadowSetup {
  glm::dmat4 worldToShadowClip{1.0};  // world → [−1, 1]³
  glm::mat4 worldToShadowClipF{1.0};  // the same in float32 (imprecise far from the origin)
  // (p − eye) → [−1, 1]³ in float32: what the GPU gets, with camera-relative positions, so that
  // precision does not depend on where in the world the camera is (DESIGN §4).
  glm::mat4 eyeRelativeToShadowClipF{1.0};
  // tsm: the map's depth is the linear light depth z_L = dot(worldToLightDepth, (p, 1)) in [−1, 1],
  // not clip z / w (TSM §4: the shadow pass writes it as gl_FragDepth, lookups compare with it);
  // the clip matrix's z row is 0 then.
  bool linearDepth = false;
  glm::dvec4 worldToLightDepth{0.0};
  glm::vec4 eyeRelativeToLightDepthF{0.0f};  // the same for (p − eye), float32
  ConvexBody body;                    // B
  bool empty = true;                  // nothing visible to shadow
  ShadowDiagnostics diagnostics;
};

// Recomputes the float32 eye-relative matrices (and tsm's depth row) of `setup` for a camera at
// `eye`: a kept map's double matrices stay, the GPU's follow the camera (DESIGN §4).
void rebaseToEye(ShadowSetup& setup, const glm::dvec3& eye);

// Where a world point lands: x, y in the map's [−1, 1]², z its depth in [−1, 1] (clip z / w, or
// the linear light depth for tsm). Double precision.
glm::dvec3 shadowMapCoordinates(const ShadowSetup& setup, const glm::dvec3& world);

// The domain of the shadow math (DESIGN §6, hard cases; docs/scene-format.md). The math itself
// runs in double and the GPU gets camera-relative positions, but scene data lives in float32
// world coordinates in places (tree instances, prop boxes, terrain samples), where a position at
// distance r from the origin is off by up to 2⁻²⁴·r. A view less deep than two such errors,
// far − near < 2⁻²³·r, cannot tell its near plane from its far plane there (a few millimetres at
// 1000 km): such views are refused as input errors. Inside the domain every method keeps the
// invariants, or falls back (computeShadowSetup).
constexpr double kMinViewDepthShare = 0x1p-23;
// Why the input is outside that domain (a one-line message with the limit), or nothing.
std::optional<std::string> outsideShadowDomain(const ShadowInput& input);

// Validates the input (throws InputError: zero or non-finite sun, near ≥ far, outside the domain
// above, ...).
void validateShadowInput(const ShadowInput& input);
// Never throws for a valid input: a method whose map cannot keep B inside it in float32 falls
// back to the focused uniform map, and failing that to no shadows (empty), with the reason in
// diagnostics.fallback.
ShadowSetup computeShadowSetup(const ShadowInput& input, ShadowMethod method);

// What `method` carries from this setup to the next frame's of the same slice (ShadowInput::carried).
double carriedToNextFrame(ShadowMethod method, const ShadowSetup& setup);

// The methods a comparison of methods runs (forest bench speed-error): every method but the
// variants of another (tsm-iterative).
std::vector<ShadowMethod> comparedShadowMethods();

// Upper bound on |x|, |y|, |z| of the shadow-clip coordinates the GPU computes for a
// camera-relative position (rounded to float32) with the float32 matrix, whatever the order of
// its float operations: the exact result plus the rounding bound. +∞ when w may be ≤ 0.
glm::dvec3 mapCoordinateBound(const glm::mat4& eyeRelativeToShadowClip, const glm::dvec3& eyeRelativePosition);

// uniform-stable: the texel size is 2·R / (size − 1 − 2·border), so R must not follow the view's
// bounding sphere (radius r) continuously, or every change of the view's far distance (the
// visible set's z_f, every frame) moves every shadow by a fraction of a texel. R takes the values
// 2^(k/4) m (steps of kStableRadiusStep octaves: at most 19% more than r), and keeps the previous
// R while r ≤ R ≤ kStableRadiusHysteresis · r: it grows at once when the view outgrows it, and
// shrinks only when the view has shrunk to 1/√2 of it. Between steps a world point keeps its
// fractional texel position; camera moves shift the map by whole texels only.
constexpr double kStableRadiusStep = 0.25;                // octaves per step
constexpr double kStableRadiusHysteresis = 1.4142135623730951;  // √2: two steps
double stableMapRadius(double sphereRadius, std::optional<double> previous);

// Eq. 8.13 with the misprint fixed (DESIGN §4): n = d / (√(z1/z0) − 1); z0, z1 negative eye-space
// depths, |z1| > |z0|. Returns +∞ when z1/z0 ≤ 1.
double lispsmNearDistance(double d, double z0, double z1);

}  // namespace forest::shadows
