#include "light_space.hpp"

#include <algorithm>
#include <cmath>

namespace forest::shadows {

using glm::dmat4;
using glm::dvec3;
using glm::dvec4;

namespace {
// Below this |sin| between body vector and light, the in-plane axis comes from the camera's up
// vector instead (a documented switch; the warp has faded out long before, see kLispsmCapFactor).
constexpr double kParallelSin = 1e-9;
// Vertices of V ∩ S within this share of its depth range of the nearest one are averaged into e.
constexpr double kNearVertexShare = 1e-3;
}  // namespace

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
namespace {
constexpr double kMinExtentShare = 1e-3;
}  // namespace

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

double angleDeg(const dvec3& a, const dvec3& b) {
  return glm::degrees(std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b)));
}

}  // namespace forest::shadows
