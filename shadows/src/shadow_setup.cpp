#include "forest/shadows/shadow_setup.hpp"

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <span>
#include <string>

#include "forest/core/error.hpp"
#include "forest/shadows/focus_body.hpp"
#include "trapezoid.hpp"

namespace forest::shadows {
namespace {

using glm::dmat4;
using glm::dvec3;
using glm::dvec4;

constexpr double kInfinity = std::numeric_limits<double>::infinity();
// Below this |sin| between body vector and light, the in-plane axis comes from the camera's up
// vector instead (a documented switch; the warp has faded out long before, see kLispsmCapFactor).
constexpr double kParallelSin = 1e-9;
// Vertices of V ∩ S within this share of its depth range of the nearest one are averaged into e.
constexpr double kNearVertexShare = 1e-3;
// B is flat across the light when its depth along the warp axis is below this share of its size.
constexpr double kFlatShare = 1e-12;

dvec3 transformPoint(const dmat4& m, const dvec3& p) {
  const dvec4 h = m * dvec4(p, 1.0);
  return dvec3(h) / h.w;
}

Aabb boundsIn(const dmat4& m, std::span<const dvec3> points) {
  Aabb box;
  for (const dvec3& p : points) box.extend(transformPoint(m, p));
  return box;
}

// §9.2.6: the body vector, the sum of the vectors from the eye to every vertex of B; the view
// direction when B gives none.
dvec3 computeBodyVector(std::span<const dvec3> bodyVertices, const Camera& camera) {
  dvec3 sum(0.0);
  for (const dvec3& p : bodyVertices) sum += p - camera.position;
  const double length = glm::length(sum);
  return length > 0.0 && std::isfinite(length) ? sum / length : camera.forward();
}

// §9.2.3: the light frame L_v⁻¹ rooted at the eye: y = −l, x = v × y, z = x × y (rows of the
// rotation). When v ∥ l the camera's up vector stands in for v.
dmat4 computeLightFrame(const dvec3& toLight, const dvec3& bodyVector, const Camera& camera,
                        const dvec3& origin) {
  const dvec3 y = toLight;
  dvec3 x = glm::cross(bodyVector, y);
  if (glm::length(x) < kParallelSin) {
    const dvec3 cameraUp = camera.up();
    x = glm::cross(cameraUp, y);
  }
  x = glm::normalize(x);
  const dvec3 z = glm::cross(x, y);
  dmat4 m(1.0);
  for (int c = 0; c < 3; ++c) {
    m[c][0] = x[c];
    m[c][1] = y[c];
    m[c][2] = z[c];
  }
  m[3] = dvec4(-glm::dot(x, origin), -glm::dot(y, origin), -glm::dot(z, origin), 1.0);
  return m;
}

// §9.2.3 (orientation ray): e_world, the average of the vertices of V ∩ S nearest to the eye.
dvec3 computeNearPoint(const ConvexBody& visibleBody, const Camera& camera) {
  const dmat4 view = camera.view();
  const auto vertices = visibleBody.vertices();
  double nearest = -kInfinity, farthest = kInfinity;
  for (const dvec3& v : vertices) {
    const double z = transformPoint(view, v).z;
    nearest = std::max(nearest, z);
    farthest = std::min(farthest, z);
  }
  const double band = kNearVertexShare * (nearest - farthest);
  dvec3 sum(0.0);
  int count = 0;
  for (const dvec3& v : vertices) {
    if (transformPoint(view, v).z >= nearest - band) {
      sum += v;
      ++count;
    }
  }
  return sum / static_cast<double>(count);
}

// §9.2.5: z0 and z1 in eye space. z0_ls lies on the plane through e parallel to the camera's near
// plane, at z = B_znear and x = e_ls.x; z1_ls is z0_ls moved to z = B_zfar (the text's "B_znear"
// for z1 is a misprint: it would give z1 = z0 and n = d/0).
std::pair<double, double> computeZ0Z1(const dmat4& lightFrame, const Camera& camera, const dvec3& eWorld,
                                      double bZnear, double bZfar) {
  const dvec3 eLs = transformPoint(lightFrame, eWorld);
  const dvec3 normalLs = glm::dvec3(lightFrame * dvec4(camera.forward(), 0.0));  // rotation only
  const double offsetLs = -glm::dot(normalLs, eLs);
  double y = eLs.y;  // any y on the plane when it contains the light axis
  if (std::abs(normalLs.y) > 1e-12) y = -(offsetLs + normalLs.z * bZnear + normalLs.x * eLs.x) / normalLs.y;
  const dvec3 z0Ls(eLs.x, y, bZnear);
  const dvec3 z1Ls(eLs.x, y, bZfar);
  const dmat4 lightToEye = camera.view() * glm::inverse(lightFrame);
  return {transformPoint(lightToEye, z0Ls).z, transformPoint(lightToEye, z1Ls).z};
}

// The warp P (§9.2.4) with strength u = 1/n, centre C = (e_ls.x, e_ls.y, B_znear + n), followed by
// the axis swap that makes light-space y the depth (DESIGN §4). In light coordinates relative to
// (C.x, C.y, B_znear), with Z = B_znear − z ≥ 0 inside B:
//   s = X,  t = −Z,  depth = −Y,  w = 1 + u·Z
// which is P_p·P_t divided by n; u → 0 is the uniform map, continuously.
dmat4 computeWarp(double u, const dvec3& eLs, double bZnear) {
  dmat4 m(0.0);
  // columns: m[col][row]
  m[0][0] = 1.0;                     // s = x − ex
  m[2][1] = 1.0;                     // t = z − bZnear
  m[1][2] = -1.0;                    // depth = −(y − ey)
  m[2][3] = -u;                      // w = 1 + u (bZnear − z)
  m[3] = dvec4(-eLs.x, -bZnear, eLs.y, 1.0 + u * bZnear);
  return m;
}

// Scale and translate so that the box fills [−1 + m, 1 − m] in x and y and [−1, 1] in z: m is
// the border kept free for the filter footprint (DESIGN §4: PCF and blur at B's border must read
// valid depth).
// An axis along which B is flat (a flat scene under a noon sun) is given a thickness of
// kMinExtentShare of B's largest extent in the map plane (of its depth extent for the depth
// axis), so the scale stays finite and float32-friendly. The map plane's floor must not come
// from the depth: B extruded 10 km towards the sun over a 3 m view would otherwise waste 3/4 of
// the map (found by the analytic aliasing figures).
constexpr double kMinExtentShare = 1e-3;

dmat4 fitToUnitCube(const Aabb& box, double borderXY) {
  const dvec3 size = box.extent();
  const double inPlane = std::max(size.x, size.y), largest = std::max(inPlane, size.z);
  const double planeFloor = inPlane > 0.0 ? kMinExtentShare * inPlane : largest > 0.0 ? kMinExtentShare * largest : 1.0;
  const double depthFloor = largest > 0.0 ? kMinExtentShare * largest : 1.0;
  const dvec3 extent = glm::max(size, dvec3(planeFloor, planeFloor, depthFloor));
  dmat4 m(1.0);
  for (int i = 0; i < 3; ++i) {
    const double scale = i < 2 ? 1.0 - borderXY : 1.0;
    m[i][i] = scale * 2.0 / extent[i];
    m[3][i] = -scale * (box.max[i] + box.min[i]) / extent[i];
  }
  return m;
}

double clipBorder(const ShadowInput& in) { return 2.0 * in.borderTexels / in.mapSize; }

// Fits an orthographic map to B in the given light frame.
dmat4 fitUniform(const dmat4& lightFrame, std::span<const dvec3> bodyVertices, double borderXY) {
  const dmat4 warp = computeWarp(0.0, dvec3(0.0), 0.0);
  const dmat4 toMap = warp * lightFrame;
  return fitToUnitCube(boundsIn(toMap, bodyVertices), borderXY) * toMap;
}

// TSM (Martin & Tan 2004): L is the uniform map fitted to B without a border (the light's
// post-perspective space of §3, orthographic for the sun); the trapezoid of §6 around B's
// footprint in L's plane, N_T applied to x, y and w only, the filter border kept after N_T; depth
// stays L's linear z (§4).
ShadowSetup computeTsm(const ShadowInput& in, bool iterative, const dmat4& lightFrame,
                       std::span<const dvec3> bodyVertices, const ConvexBody& visible, ShadowSetup setup) {
  const Camera& camera = in.camera;
  const dmat4 L = fitUniform(lightFrame, bodyVertices, 0.0);
  auto plane = [&](const dvec3& p) { return glm::dvec2(transformPoint(L, p)); };
  TrapezoidInput t;
  for (const dvec3& p : bodyVertices) t.footprint.push_back(plane(p));
  t.eye = plane(camera.position);
  const auto visibleVertices = visible.vertices();
  dvec3 centre(0.0);
  double nearest = kInfinity, farthest = -kInfinity;
  for (const dvec3& p : visibleVertices) {
    centre += p;
    const double depth = glm::dot(p - camera.position, camera.forward());
    nearest = std::min(nearest, depth);
    farthest = std::max(farthest, depth);
  }
  t.centre = plane(centre / static_cast<double>(visibleVertices.size()));
  // §6.4: the focus region is the first focusShare of the depth range the visible part spans.
  t.focusPoint = plane(camera.position + camera.forward() * (nearest + in.tsmFocusShare * (farthest - nearest)));
  t.iterative = iterative;
  t.mapLines = in.mapSize;

  setup.linearDepth = true;
  setup.worldToLightDepth = glm::dvec4(L[0][2], L[1][2], L[2][2], L[3][2]);  // L's z row
  const std::optional<Trapezoid> trapezoid = computeTrapezoid(t, setup.diagnostics.fallback);
  // (x_T·w, y_T·w, w) from L's (x, y, 1), the border kept free after N_T; clip z = 0 (the depth
  // is the linear row above). Without a trapezoid: L itself with the border.
  glm::dmat3 n(1.0);
  if (trapezoid) {
    n = trapezoid->toSquare;
    ShadowDiagnostics& d = setup.diagnostics;
    d.tsmLambda = trapezoid->lambda;
    d.tsmFocus = trapezoid->focus;
    d.tsmEta = trapezoid->eta;
    d.tsmXi = trapezoid->xi;
    d.tsmFocusArea = trapezoid->focusArea;
  }
  const double keep = 1.0 - clipBorder(in);
  dmat4 nt(0.0);
  for (int c = 0; c < 3; ++c) {
    const int column = c < 2 ? c : 3;  // L's x, y and the constant
    nt[column][0] = keep * n[c][0];
    nt[column][1] = keep * n[c][1];
    nt[column][3] = n[c][2];
  }
  setup.worldToShadowClip = nt * L;
  return setup;
}

double angleDeg(const dvec3& a, const dvec3& b) {
  return glm::degrees(std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b)));
}

// Each shrink aims this far inside the bound: rounding the shrunk matrix to float32 moves the
// result again by up to ~u·Σ|m·p|, which a fixed 4u step chases for thousands of steps when B is
// thin (found with held-back seeds: 2e-8 per step); growing the margin 4× per attempt settles in a
// few, and the first attempt is the tightest.
double shrinkMargin(int attempt) { return 4.0 * kFloatUnitRoundoff * std::ldexp(1.0, 2 * attempt); }

// The float32 matrices, with B kept inside [−1, 1]³ as the GPU computes it: a fit exact in
// double can leave B's vertices outside by ~1e-3 after float32 rounding when B is 10⁴ times
// longer than wide (camera-relative positions of 1e5 m keep only ~6 mm). Each shadow-clip axis
// is shrunk about 0 until the worst case (float matrix, float positions, plus the bound on the
// GPU's rounding) is inside: see mapCoordinateBound. Nothing when no shrink does it (w may reach
// 0 on the float32 path): the caller falls back.
std::optional<ShadowSetup> finish(ShadowSetup setup, const dvec3& eye) {
  const auto vertices = setup.body.vertices();
  if (setup.linearDepth) {
    // The same for the linear depth row (tsm): shrink it about 0 until B's depth is inside
    // [−1, 1] as the GPU evaluates it in float32 (γ₄ bound, as in mapCoordinateBound).
    for (int attempt = 0;; ++attempt) {
      const glm::dvec4& r = setup.worldToLightDepth;
      setup.eyeRelativeToLightDepthF = glm::vec4(dvec3(r), r.w + glm::dot(dvec3(r), eye));
      const glm::dvec4 rowF(setup.eyeRelativeToLightDepthF);
      double worst = 0.0;
      for (const dvec3& v : vertices) {
        const glm::dvec4 p(dvec3(glm::vec3(v - eye)), 1.0);
        const double exact = glm::dot(rowF, p), magnitude = glm::dot(glm::abs(rowF), glm::abs(p));
        worst = std::max(worst, std::abs(exact) + 4.0 * kFloatUnitRoundoff / (1.0 - 4.0 * kFloatUnitRoundoff) * magnitude);
      }
      if (worst <= 1.0) break;
      if (attempt == 8) return std::nullopt;
      setup.worldToLightDepth *= (1.0 - shrinkMargin(attempt)) / worst;
    }
  }
  for (int attempt = 0;; ++attempt) {
    setup.eyeRelativeToShadowClipF = glm::mat4(setup.worldToShadowClip * glm::translate(dmat4(1.0), eye));
    dvec3 worst(0.0);
    for (const dvec3& v : vertices) worst = glm::max(worst, mapCoordinateBound(setup.eyeRelativeToShadowClipF, v - eye));
    if (worst.x <= 1.0 && worst.y <= 1.0 && worst.z <= 1.0) break;
    if (attempt == 8) return std::nullopt;
    for (int axis = 0; axis < 3; ++axis) {
      if (worst[axis] <= 1.0) continue;
      const double shrink = (1.0 - shrinkMargin(attempt)) / worst[axis];
      for (int c = 0; c < 4; ++c) setup.worldToShadowClip[c][axis] *= shrink;
      setup.diagnostics.floatShrink = std::max(setup.diagnostics.floatShrink, 1.0 - shrink);
    }
  }
  setup.worldToShadowClipF = glm::mat4(setup.worldToShadowClip);
  setup.diagnostics.bodyVertices = vertices.size();
  return setup;
}

}  // namespace

ShadowMethod parseShadowMethod(std::string_view name) {
  if (name == "uniform") return ShadowMethod::Uniform;
  if (name == "uniform-stable") return ShadowMethod::UniformStable;
  if (name == "lispsm") return ShadowMethod::Lispsm;
  if (name == "tsm") return ShadowMethod::Tsm;
  if (name == "tsm-iterative") return ShadowMethod::TsmIterative;
  throw InputError(fmt::format("shadow method '{}': expected uniform, uniform-stable, lispsm, tsm or tsm-iterative", name));
}

std::vector<std::string> shadowMethodNames() {
  std::vector<std::string> names;
  for (ShadowMethod m : {ShadowMethod::Uniform, ShadowMethod::UniformStable, ShadowMethod::Lispsm, ShadowMethod::Tsm,
                         ShadowMethod::TsmIterative})
    names.emplace_back(shadowMethodName(m));
  return names;
}

std::string_view shadowMethodName(ShadowMethod method) {
  switch (method) {
    case ShadowMethod::Uniform: return "uniform";
    case ShadowMethod::UniformStable: return "uniform-stable";
    case ShadowMethod::Lispsm: return "lispsm";
    case ShadowMethod::Tsm: return "tsm";
    case ShadowMethod::TsmIterative: return "tsm-iterative";
  }
  return "?";
}

dvec3 mapCoordinateBound(const glm::mat4& eyeRelativeToShadowClip, const dvec3& eyeRelativePosition) {
  // Rounding of a float dot product of 4 terms, in any order or with FMA: |error| ≤ γ₄ Σ|aᵢbᵢ|,
  // γ₄ = 4u / (1 − 4u) (Higham, Accuracy and Stability, §3.1); the divide by w adds u.
  constexpr double u = kFloatUnitRoundoff, gamma4 = 4.0 * u / (1.0 - 4.0 * u);
  const glm::dvec4 p(glm::dvec3(glm::vec3(eyeRelativePosition)), 1.0);  // what the GPU gets
  const glm::dmat4 m(eyeRelativeToShadowClip);
  glm::dvec4 h(0.0), magnitude(0.0);
  for (int c = 0; c < 4; ++c) {
    h += m[c] * p[c];
    magnitude += glm::abs(m[c] * p[c]);
  }
  const glm::dvec4 error = gamma4 * magnitude;
  const double w = h.w - error.w;
  if (!(w > 0.0)) return dvec3(kInfinity);
  dvec3 bound;
  for (int i = 0; i < 3; ++i) bound[i] = ((std::abs(h[i]) + error[i]) / w) * (1.0 + u);
  return bound;
}

dvec3 shadowMapCoordinates(const ShadowSetup& setup, const dvec3& world) {
  const dvec4 h = setup.worldToShadowClip * dvec4(world, 1.0);
  const double depth = setup.linearDepth ? glm::dot(setup.worldToLightDepth, dvec4(world, 1.0)) : h.z / h.w;
  return dvec3(h.x / h.w, h.y / h.w, depth);
}

double stableMapRadius(double sphereRadius, std::optional<double> previous) {
  if (!(sphereRadius > 0.0) || !std::isfinite(sphereRadius)) return sphereRadius;
  if (previous && *previous >= sphereRadius && *previous <= kStableRadiusHysteresis * sphereRadius) return *previous;
  return std::exp2(std::ceil(std::log2(sphereRadius) / kStableRadiusStep) * kStableRadiusStep);
}

double lispsmNearDistance(double d, double z0, double z1) {
  const double ratio = z1 / z0;
  if (!(ratio > 1.0) || !std::isfinite(ratio)) return kInfinity;
  return d / (std::sqrt(ratio) - 1.0);
}

void validateShadowInput(const ShadowInput& in) {
  const Camera& c = in.camera;
  const double sun = glm::length(in.sunDirection);
  if (!std::isfinite(sun) || sun < 1e-300) throw InputError("sun_dir: expected a finite non-zero vector");
  for (double v : {c.position.x, c.position.y, c.position.z, c.yaw, c.pitch, c.roll, c.fovy, c.aspect, c.near, c.far}) {
    if (!std::isfinite(v)) throw InputError("camera: values must be finite");
  }
  if (!(c.near > 0.0) || !(c.far > c.near)) throw InputError("camera: expected 0 < near < far");
  if (!(c.fovy > 0.0) || !(c.fovy < std::numbers::pi)) throw InputError("camera: expected 0 < fovy < 180°");
  if (!(c.aspect > 0.0)) throw InputError("camera: expected aspect > 0");
  if (!in.scene.valid() || !std::isfinite(in.scene.diagonal())) throw InputError("scene box: expected finite min <= max");
  if (in.nFar && !(*in.nFar > c.near)) throw InputError("n_far: expected a distance greater than near");
  if (in.nNear && !std::isfinite(*in.nNear)) throw InputError("n_near: expected a finite distance");
  if (const std::optional<std::string> outside = outsideShadowDomain(in)) throw InputError(*outside);
  if (in.mapSize < 16 || in.mapSize > kMaxMapSize)
    throw InputError(fmt::format("map size {}: expected 16 to {} texels", in.mapSize, kMaxMapSize));
  if (in.borderTexels < 0 || 4 * in.borderTexels >= in.mapSize)
    throw InputError(fmt::format("border {} texels: expected 0 to a quarter of the map size", in.borderTexels));
}

namespace {

// computeShadowSetup's note when float32 forces the uniform map (a literal per method).
std::string_view float32FallbackNote(ShadowMethod method) {
  switch (method) {
    case ShadowMethod::Uniform: break;
    case ShadowMethod::UniformStable: return "uniform-stable cannot keep B inside its map in float32: uniform";
    case ShadowMethod::Lispsm: return "lispsm cannot keep B inside its map in float32: uniform";
    case ShadowMethod::Tsm: return "tsm cannot keep B inside its map in float32: uniform";
    case ShadowMethod::TsmIterative: return "tsm-iterative cannot keep B inside its map in float32: uniform";
  }
  return "uniform cannot keep B inside its map in float32";
}

// One method's setup; nothing when float32 cannot keep B inside its map (see finish).
std::optional<ShadowSetup> computeMethodSetup(const ShadowInput& in, ShadowMethod method) {
  const Camera& camera = in.camera;
  const dvec3 l = glm::normalize(in.sunDirection);
  const dvec3 toLight = -l;

  ShadowSetup setup;
  setup.body = computeFocusBody(camera, l, in.scene, in.receivers);
  if (setup.body.empty()) {
    setup.diagnostics.fallback = "empty focus body";
    return finish(setup, camera.position);
  }
  setup.empty = false;
  const auto bodyVertices = setup.body.vertices();
  const dvec3 bodyVector = computeBodyVector(bodyVertices, camera);
  setup.diagnostics.gammaDeg = angleDeg(bodyVector, l);
  if (method == ShadowMethod::UniformStable) {
    // World-fixed in-plane axes (the world axis least parallel to the light), extent from V's
    // bounding sphere (independent of the camera's rotation), its radius quantised to steps with
    // hysteresis (stableMapRadius), origin snapped to texels.
    const dvec3 axis = std::abs(l.z) < 0.9 ? dvec3(0, 0, 1) : dvec3(1, 0, 0);
    const dmat4 frame = computeLightFrame(toLight, axis, camera, dvec3(0.0));
    const ConvexBody frustum = viewFrustumBody(camera);
    const auto corners = frustum.vertices();
    dvec3 centre(0.0);
    for (const dvec3& p : corners) centre += p;
    centre /= static_cast<double>(corners.size());
    double sphere = 0.0;
    for (const dvec3& p : corners) sphere = std::max(sphere, glm::distance(p, centre));
    const double radius = stableMapRadius(sphere, in.previousStableRadius);
    setup.diagnostics.stableRadius = radius;
    const dmat4 toMap = computeWarp(0.0, dvec3(0.0), 0.0) * frame;
    const dvec3 centreMap = transformPoint(toMap, centre);
    // mapSize texels of equal size cover the sphere's square plus one texel of snapping slack
    // plus the filter border on each side; the map's origin sits on a whole texel.
    const double texel = 2.0 * radius / (in.mapSize - 1 - 2 * in.borderTexels);
    Aabb box = boundsIn(toMap, bodyVertices);
    for (int a = 0; a < 2; ++a) {
      box.min[a] = (std::floor((centreMap[a] - radius) / texel) - in.borderTexels) * texel;
      box.max[a] = box.min[a] + in.mapSize * texel;
    }
    setup.worldToShadowClip = fitToUnitCube(box, 0.0) * toMap;
    return finish(setup, camera.position);
  }

  // V ∩ S (∩ receivers): what is seen. B contains it in exact arithmetic, but B and this body are
  // clipped separately, with tolerances relative to each body's size: a B 10⁵ times taller than
  // wide can lose 1e-3 of its width to them. The fitted maps take both, so every visible point
  // lands inside the map whatever the tolerances did (found with held-back seeds); the stable
  // map above covers the whole view's sphere anyway.
  ConvexBody visible = viewFrustumBody(camera);
  visible.clip(in.scene);
  if (in.receivers) visible.clip(*in.receivers);
  std::pmr::vector<dvec3> fitVertices(bodyVertices.begin(), bodyVertices.end(), convexBodyMemory());
  for (const dvec3& v : visible.vertices()) fitVertices.push_back(v);

  // §9.2.3: light frame L (L_r is the identity for directional lights: the body vector already
  // points "up" the map), rooted at the eye.
  const dmat4 lightFrame = computeLightFrame(toLight, bodyVector, camera, camera.position);
  if (method == ShadowMethod::Uniform) {
    setup.worldToShadowClip = fitUniform(lightFrame, fitVertices, clipBorder(in));
    return finish(setup, camera.position);
  }

  if (method == ShadowMethod::Tsm || method == ShadowMethod::TsmIterative)
    return finish(computeTsm(in, method == ShadowMethod::TsmIterative, lightFrame, fitVertices, visible.empty() ? setup.body : visible, setup), camera.position);

  // §9.2.4: B in light space; the warp runs along −z from B_znear to B_zfar.
  const Aabb bLs = boundsIn(lightFrame, bodyVertices);
  const dvec3 eWorld = computeNearPoint(visible.empty() ? setup.body : visible, camera);
  const dvec3 eLs = transformPoint(lightFrame, eWorld);

  // §9.2.5: n from eq. 8.13, on B or on the body of the virtual frustum (far = n_far, near = n_near).
  Aabb nBox = bLs;
  Camera virtualCamera = camera;
  if (in.nFar && *in.nFar != camera.far) virtualCamera.far = *in.nFar;
  if (in.nNear && *in.nNear > camera.near && *in.nNear < 0.999 * virtualCamera.far) virtualCamera.near = *in.nNear;
  if (virtualCamera.near != camera.near || virtualCamera.far != camera.far) {
    const ConvexBody virtualBody = computeFocusBody(virtualCamera, l, in.scene, in.receivers);
    if (!virtualBody.empty()) nBox = boundsIn(lightFrame, virtualBody.vertices());
  }
  const double d = nBox.max.z - nBox.min.z;
  const auto [z0, z1] = computeZ0Z1(lightFrame, camera, eWorld, nBox.max.z, nBox.min.z);
  const double nOpt = lispsmNearDistance(d, z0, z1);
  ShadowDiagnostics& diag = setup.diagnostics;
  diag.z0 = z0;
  diag.z1 = z1;
  diag.d = d;
  // The cap scales with B's depth along the warp axis; a B flat across the light has none, and
  // then nothing to warp: the cap falls back to B's size.
  const double depthScale = std::max(d, bLs.max.z - bLs.min.z);
  const bool flatAcrossLight = !(depthScale > kFlatShare * bLs.diagonal());
  diag.nCap = kLispsmCapFactor * (flatAcrossLight ? bLs.diagonal() : depthScale);
  diag.nOptimal = flatAcrossLight || !(nOpt > 0.0) ? diag.nCap : std::min(nOpt, diag.nCap);
  double n = diag.nOptimal;
  if (in.previousN && *in.previousN > 0.0 && std::isfinite(*in.previousN))  // over time (kNearDistanceSmoothing)
    n = std::min(*in.previousN + kNearDistanceSmoothing * (diag.nOptimal - *in.previousN), diag.nCap);
  diag.n = n;
  // Fade: the warp strength 1/n falls linearly to 0 as n reaches the cap.
  const double u = !flatAcrossLight && n > 0.0 ? std::max(0.0, 1.0 / n - 1.0 / diag.nCap) : 0.0;
  diag.warp = u;
  if (flatAcrossLight) diag.fallback = "B flat across the light: uniform";
  else if (u == 0.0) diag.fallback = "n at cap: uniform";

  const dmat4 toMap = computeWarp(u, eLs, bLs.max.z) * lightFrame;
  setup.worldToShadowClip = fitToUnitCube(boundsIn(toMap, fitVertices), clipBorder(in)) * toMap;
  return finish(setup, camera.position);
}

}  // namespace

std::optional<std::string> outsideShadowDomain(const ShadowInput& in) {
  const Camera& c = in.camera;
  const double distance = glm::length(c.position);
  if (!(c.far - c.near >= kMinViewDepthShare * distance))
    return fmt::format("camera: a view {:.3g} m deep (far - near) at {:.3g} m from the world origin is outside the "
                       "float32 domain: it must be at least 2^-23 = {:.3g} of that distance deep ({:.3g} m)",
                       c.far - c.near, distance, kMinViewDepthShare, kMinViewDepthShare * distance);
  return std::nullopt;
}

ShadowSetup computeShadowSetup(const ShadowInput& in, ShadowMethod method) {
  validateShadowInput(in);
  if (std::optional<ShadowSetup> setup = computeMethodSetup(in, method)) return *setup;
  // Float32 cannot keep B inside this method's map (w reaches 0 on the GPU's path): the focused
  // uniform map, whose w is 1; failing that, no shadows this time. Never an exception out of a
  // frame.
  if (method != ShadowMethod::Uniform) {
    if (std::optional<ShadowSetup> setup = computeMethodSetup(in, ShadowMethod::Uniform)) {
      setup->diagnostics.fallback = float32FallbackNote(method);
      return *setup;
    }
  }
  ShadowSetup none;
  none.body = computeFocusBody(in.camera, glm::normalize(in.sunDirection), in.scene, in.receivers);
  none.diagnostics.fallback = "no map keeps B inside it in float32: no shadows";
  none.eyeRelativeToShadowClipF = glm::mat4(none.worldToShadowClip * glm::translate(dmat4(1.0), in.camera.position));
  none.worldToShadowClipF = glm::mat4(none.worldToShadowClip);
  return none;
}

}  // namespace forest::shadows
