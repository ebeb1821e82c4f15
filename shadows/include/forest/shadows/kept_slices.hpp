#pragma once
// Kept slices (DESIGN §12, issue "Shadows that hold still"): a slice's map keeps its matrices from
// frame to frame while what it must cover stays inside what it covers, so its texel grid holds
// still in the world and shadow edges do not swim as the camera moves. Every method refits each
// frame to the view; a warped map (lispsm, tsm) then moves every texel every frame.
//
// Per slice, each frame: this frame's setup is computed as without keeping (the fresh fit). The
// kept matrices stay when
//   - the method, map size and border are the same and the sun has moved less than sunDeg;
//   - B (this frame's focus body) lies inside the kept map, its filter border included, as the GPU
//     computes it (float32 matrices for this frame's eye, mapCoordinateBound): every lookup reads
//     texels the shadow pass draws, so keeping never changes which casters count;
//   - the kept map's texels are at most texelGrowth times the fresh fit's (side) at every vertex
//     of the visible part of the slice (V ∩ S ∩ R from the nearest visible depth): the error a kept
//     map may add is bounded.
// A slice's first frame (or the first after a cut) takes the fresh fit, as without keeping.
// Otherwise the slice refits, its map also holding the focus body of the camera `horizonFrames`
// ahead (its motion of the last frame continued: position and yaw/pitch) and a slack, with the warp
// snapped (ShadowInput::snapWarp): the frames between fit inside it (a translate of a convex body
// stays in the hull of its ends), and successive refits of a slow camera tend to land on the same
// lattice values. The margin costs texels: a refit whose texels exceed texelGrowth takes half the
// horizon, down to one frame, then the fresh fit.
#include <array>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "forest/shadows/cascades.hpp"
#include "forest/shadows/shadow_setup.hpp"

namespace forest::shadows {

struct KeepLimits {
  int horizonFrames = 8;      // a refit covers the camera's last motion continued this many frames
  // ... and keeps this share of the map's width free beyond its border on each side, for what the
  // motion does not predict (the visible set's bounds and z_f, the splits, changing every frame)
  double slackShare = 0.02;
  double sunDeg = 0.01;       // the sun moved more than this: refit (the map projects along the sun)
  double texelGrowth = 1.25;  // the kept map's texel side over a fresh fit's, at most, where visible
};

// Why a slice refitted (or "" when it kept its map).
struct SliceKeeping {
  bool kept = false;
  int keptFrames = 0;          // frames in a row this slice's map was kept (0: refitted now)
  std::string_view refit;      // "first", "method", "sun", "outside", "texels", "empty", "stable"
                               // (a method that holds still by itself: never kept); "" when kept
};

// Whether `method`'s map holds still by its own construction (uniform-stable): it is never kept.
bool holdsStillByItself(ShadowMethod method);

// `camera` moved on by `frames` times its motion since `last` (position, yaw and pitch).
Camera extrapolatedCamera(const Camera& camera, const Camera& last, double frames);

// The largest ratio, over `points`, of the texel side of map `a` to that of map `b` (texels per
// area across the light `l`, from the Jacobian of each projective map at the point). +∞ when `a`
// cannot place a point that `b` can.
double texelSideRatio(const ShadowSetup& a, const ShadowSetup& b, std::span<const glm::dvec3> points, const glm::dvec3& l);

// The shortest move across the light `l` that carries a point by one texel of a `mapSize`² map, the
// least over `points` (metres): one texel (2 / mapSize of the map's [−1, 1]) over the largest
// singular value of the map's Jacobian across the light there. +∞ when no point can be placed.
double finestTexelSide(const ShadowSetup& setup, int mapSize, std::span<const glm::dvec3> points, const glm::dvec3& l);

class KeptSlices {
 public:
  // This frame's setup of `slice` (checked input as computeShadowSetup's): the kept map when it
  // still holds (rebased to this frame's eye, with this frame's B), else a refit with margin.
  ShadowSetup setup(const ShadowInput& input, ShadowMethod method, int slice, const KeepLimits& limits, SliceKeeping& keeping);
  // Forgets every kept map (a camera cut, keeping turned off).
  void reset();

 private:
  // The refit: the map also holding B of the camera extrapolated over the horizon, halved until its
  // texels are within the limit. Nothing when even one frame's are not.
  std::optional<ShadowSetup> refit(const ShadowInput& input, ShadowMethod method, const ShadowSetup& fresh,
                                   std::span<const glm::dvec3> visible, const KeepLimits& limits, const Camera& last);

  struct Kept {
    bool valid = false;
    ShadowSetup setup;
    ShadowMethod method = ShadowMethod::Uniform;
    glm::dvec3 sun{0.0};
    int mapSize = 0, borderTexels = 0;
    int frames = 0;
  };
  // `visible`: the vertices of the slice's visible part, where texels are compared.
  std::string_view whyRefit(const Kept& kept, const ShadowInput& input, ShadowMethod method, const ShadowSetup& fresh,
                            std::span<const glm::dvec3> visible, const KeepLimits& limits) const;
  std::array<Kept, kMaxCascades> kept_{};
  // Each slice's camera of the last frame: the motion a refit extrapolates.
  std::array<std::optional<Camera>, kMaxCascades> lastCamera_{};
  std::vector<glm::dvec3> alsoCover_;  // what a refit's map also holds: B ahead, the depth slack (ShadowInput::alsoCover)
};

}  // namespace forest::shadows
