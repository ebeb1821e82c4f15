#include "forest/shadows/aliasing.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace forest::shadows {
namespace {

using glm::dvec2;
using glm::dvec3;
using glm::dvec4;

// ∂(h.xy / h.w)/∂p for h = M·(p, 1): the exact Jacobian of a projective map, rows x and y.
struct Jacobian2x3 {
  dvec3 x, y;
  dvec2 operator*(const dvec3& v) const { return {glm::dot(x, v), glm::dot(y, v)}; }
};

Jacobian2x3 projectiveJacobian(const glm::dmat4& m, const dvec3& p) {
  const dvec4 h = m * dvec4(p, 1.0);
  auto row = [&](int r) { return dvec3(m[0][r], m[1][r], m[2][r]); };
  const dvec3 w = row(3);
  return {(row(0) - (h.x / h.w) * w) / h.w, (row(1) - (h.y / h.w) * w) / h.w};
}

bool inside(const Aabb& box, const dvec3& p) {
  const double slack = 1e-9 * std::max(1.0, box.diagonal());
  return glm::all(glm::greaterThanEqual(p, box.min - slack)) && glm::all(glm::lessThanEqual(p, box.max + slack));
}

}  // namespace

ErrorStatistics summarise(std::vector<double> values) {
  ErrorStatistics s;
  s.samples = static_cast<int>(values.size());
  if (values.empty()) return s;
  double sum = 0.0;
  for (double v : values) {
    s.max = std::max(s.max, v);
    sum += v;
  }
  s.mean = sum / static_cast<double>(values.size());
  const size_t k = static_cast<size_t>(std::ceil(0.95 * static_cast<double>(values.size()))) - 1;
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(k), values.end());
  s.p95 = values[k];
  return s;
}

double perspectiveAliasing(const ShadowSetup& setup, const Camera& camera, const dvec3& point) {
  const Jacobian2x3 j = projectiveJacobian(setup.worldToShadowClip, point);
  // Light rays land on one texel: the map's Jacobian vanishes along the light direction.
  const dvec3 light = glm::normalize(glm::cross(j.x, j.y));
  dvec3 along = camera.forward() - glm::dot(camera.forward(), light) * light;
  if (glm::length(along) < 1e-9) along = camera.up() - glm::dot(camera.up(), light) * light;  // view along the light
  along = glm::normalize(along);
  const double z = glm::dot(point - camera.position, camera.forward());
  const double mapUnitsPerMetre = 0.5 * glm::length(j * along);  // s ∈ [0, 1] across the map
  return 1.0 / (z * mapUnitsPerMetre);
}

std::optional<SurfaceAliasing> surfaceAliasing(const ShadowSetup& setup, const Camera& camera, const dvec3& point,
                                               const dvec3& normal, const dvec3& lightDirection, int mapSize, int width,
                                               int height) {
  const dvec3 n = glm::normalize(normal);
  const dvec3 toEye = glm::normalize(camera.position - point);
  if (!(glm::dot(n, -glm::normalize(lightDirection)) > kGrazingCos) || !(glm::dot(n, toEye) > kGrazingCos))
    return std::nullopt;
  // An orthonormal basis of the surface's plane.
  const dvec3 helper = std::abs(n.x) < 0.9 ? dvec3(1, 0, 0) : dvec3(0, 1, 0);
  const dvec3 t1 = glm::normalize(glm::cross(n, helper)), t2 = glm::cross(n, t1);
  const Jacobian2x3 map = projectiveJacobian(setup.worldToShadowClip, point);
  const Jacobian2x3 screen = projectiveJacobian(camera.projection() * camera.view(), point);
  // Texels and pixels per metre along t1, t2 (columns).
  const glm::dmat2 texels(0.5 * mapSize * (map * t1), 0.5 * mapSize * (map * t2));
  const glm::dmat2 pixels(dvec2(0.5 * width, 0.5 * height) * (screen * t1), dvec2(0.5 * width, 0.5 * height) * (screen * t2));
  if (!(std::abs(glm::determinant(texels)) > 0.0)) return std::nullopt;
  const glm::dmat2 a = pixels * glm::inverse(texels);  // pixels per texel step
  // Largest singular value of a 2×2: √ of the largest eigenvalue of AᵀA.
  const glm::dmat2 ata = glm::transpose(a) * a;
  const double trace = ata[0][0] + ata[1][1], det = glm::determinant(ata);
  SurfaceAliasing s;
  s.footprint = std::sqrt(0.5 * trace + std::sqrt(std::max(0.0, 0.25 * trace * trace - det)));
  s.alongS = glm::length(a[0]);
  s.alongT = glm::length(a[1]);
  return s;
}

AliasingReport analyseAliasing(const ShadowInput& in, const ShadowSetup& setup, const AliasingOptions& options) {
  AliasingReport report;
  if (setup.empty) return report;
  const Camera& camera = in.camera;
  const double tanY = std::tan(0.5 * camera.fovy), tanX = tanY * camera.aspect;
  const double pixelsPerTangent = options.height / (2.0 * tanY);
  std::vector<double> perspective, perspectivePixels, surface;
  double maxS = 0.0, maxT = 0.0;
  for (int i = 0; i < options.raysPerAxis; ++i) {
    for (int k = 0; k < options.raysPerAxis; ++k) {
      const double sx = (2.0 * i + 1.0) / options.raysPerAxis - 1.0, sy = (2.0 * k + 1.0) / options.raysPerAxis - 1.0;
      const dvec3 ray = camera.forward() + sx * tanX * camera.right() + sy * tanY * camera.up();  // eye depth 1
      for (int d = 0; d < options.depthsPerRay; ++d) {
        const double t = options.depthsPerRay > 1 ? static_cast<double>(d) / (options.depthsPerRay - 1) : 0.0;
        const double z = camera.near * std::pow(camera.far / camera.near, t);
        const dvec3 p = camera.position + z * ray;
        if (!inside(in.scene, p) || (in.receivers && !inside(*in.receivers, p))) continue;
        const double e = perspectiveAliasing(setup, camera, p);
        if (!std::isfinite(e)) continue;
        perspective.push_back(e);
        perspectivePixels.push_back(e * pixelsPerTangent / in.mapSize);
        const auto s = surfaceAliasing(setup, camera, p, options.surfaceNormal, in.sunDirection, in.mapSize, options.width,
                                       options.height);
        if (s && std::isfinite(s->footprint)) {
          surface.push_back(s->footprint);
          maxS = std::max(maxS, s->alongS);
          maxT = std::max(maxT, s->alongT);
        }
      }
    }
  }
  report.perspective = summarise(std::move(perspective));
  report.perspectivePixels = summarise(std::move(perspectivePixels));
  report.surfacePixels = summarise(std::move(surface));
  report.storageFactor = static_cast<double>(in.mapSize) * in.mapSize * maxS * maxT / (static_cast<double>(options.width) * options.height);
  // Eq. 8.4 over the depth range LiSPSM equalizes (§9.2.5 z0, z1).
  const ShadowDiagnostics lispsm = computeShadowSetup(in, ShadowMethod::Lispsm).diagnostics;
  if (lispsm.z0 < 0.0 && lispsm.z1 / lispsm.z0 > 1.0) report.floor = std::log(lispsm.z1 / lispsm.z0);
  return report;
}

}  // namespace forest::shadows
