#pragma once
// Analytic aliasing error of a shadow setup (thesis §8.2, eq. 8.1; DESIGN §5), without GL: how
// many screen pixels one shadow-map texel covers, from the exact Jacobians of the two projections.
//
//  - Perspective part (eq. 8.1 with the projection term cos α / cos β = 1): dp/ds = (1/z)·dz/ds,
//    measured along the view direction projected into the map's plane (the axis a warp acts on,
//    the thesis' 1D analysis): z the eye depth, dz the world length of a map step ds, s in map
//    units [0, 1] across the whole map, p in tangent units (y/z). "Relative units": eq. 8.2/8.9
//    give uniform (z_f − z_n)/z and LiSPSM (z − z_n + n)²(z_f − z_n) / (z n (n + z_f − z_n)).
//    Pixels per texel = relative · (H / (2 tan(fovy/2))) / R.
//  - With a surface normal (the projection term included, both map axes): the largest singular
//    value of J_screen · J_map⁻¹ on the surface's plane, pixels per texel; m_s, m_t the pixel
//    lengths of one texel step along the map's axes (Lloyd et al.'s storage factor
//    S = R² · max m_s · max m_t / (W · H)).
//  - Floor (eq. 8.4): the logarithmic parameterization's constant error ln(z1/z0), z0 and z1 the
//    eye-space depth range a warp can act on (§9.2.5, as LiSPSM computes it).
#include <glm/glm.hpp>

#include <optional>
#include <vector>

#include "forest/core/camera.hpp"
#include "forest/shadows/shadow_setup.hpp"

namespace forest::shadows {

// Perspective aliasing at a world point, relative units (see above).
double perspectiveAliasing(const ShadowSetup& setup, const Camera& camera, const glm::dvec3& point);

struct SurfaceAliasing {
  double footprint = 0.0;  // largest singular value of J_screen · J_map⁻¹: pixels per texel
  double alongS = 0.0;     // m_s: pixels covered by one texel step along the map's x
  double alongT = 0.0;     // m_t: the same along the map's y
};
// With the surface's normal; nullopt where the surface faces away from the light or the eye, or
// is within kGrazingCos of parallel to either (the error is unbounded there: projection aliasing).
constexpr double kGrazingCos = 1e-3;
std::optional<SurfaceAliasing> surfaceAliasing(const ShadowSetup& setup, const Camera& camera, const glm::dvec3& point,
                                               const glm::dvec3& normal, const glm::dvec3& lightDirection, int mapSize,
                                               int width, int height);

struct ErrorStatistics {
  double max = 0.0, p95 = 0.0, mean = 0.0;
  int samples = 0;
};

// max, p95 (the value 95% of the samples do not exceed) and mean; zeros when empty.
ErrorStatistics summarise(std::vector<double> values);

struct AliasingOptions {
  int width = 1280, height = 720;       // screen pixels
  int raysPerAxis = 24;                 // screen grid of sample rays
  int depthsPerRay = 48;                // log-spaced eye depths from near to far on each ray
  glm::dvec3 surfaceNormal{0.0, 1.0, 0.0};  // for the surface figures (level ground)
};

struct AliasingReport {
  ErrorStatistics perspective;        // relative units
  ErrorStatistics perspectivePixels;  // pixels per texel
  ErrorStatistics surfacePixels;      // pixels per texel, with the surface normal
  double floor = 0.0;                 // ln(z1/z0), relative units (eq. 8.4); 0 when undefined
  double storageFactor = 0.0;         // Lloyd's S
};

// Statistics over sample points of V ∩ S (∩ receivers): rays through a grid of screen points,
// log-spaced depths on each. All zero when nothing is visible.
AliasingReport analyseAliasing(const ShadowInput& input, const ShadowSetup& setup, const AliasingOptions& options = {});

}  // namespace forest::shadows
