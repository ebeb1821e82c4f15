#pragma once
// The light-space steps every shadow method shares (thesis §9.2; module-internal): the light frame
// L, the body vector, the near point e, z0 and z1, the warp P and the fit of a map to a box. Each
// method's file composes them (shadow_methods.hpp).
#include <glm/glm.hpp>

#include <limits>
#include <span>
#include <utility>

#include "forest/core/bounds.hpp"
#include "forest/core/camera.hpp"
#include "forest/core/convex_body.hpp"
#include "forest/shadows/shadow_setup.hpp"

namespace forest::shadows {

inline constexpr double kInfinity = std::numeric_limits<double>::infinity();

glm::dvec3 transformPoint(const glm::dmat4& m, const glm::dvec3& p);  // with the divide by w
Aabb boundsIn(const glm::dmat4& m, std::span<const glm::dvec3> points);

// §9.2.6: the body vector, the sum of the vectors from the eye to every vertex of B; the view
// direction when B gives none.
glm::dvec3 computeBodyVector(std::span<const glm::dvec3> bodyVertices, const Camera& camera);

// §9.2.3: the light frame L_v⁻¹ rooted at `origin`: y = −l, x = v × y, z = x × y (rows of the
// rotation). When v ∥ l the camera's up vector stands in for v.
glm::dmat4 computeLightFrame(const glm::dvec3& toLight, const glm::dvec3& bodyVector, const Camera& camera, const glm::dvec3& origin);

// §9.2.3 (orientation ray): e_world, the average of the vertices of V ∩ S nearest to the eye.
glm::dvec3 computeNearPoint(const ConvexBody& visibleBody, const Camera& camera);

// §9.2.5: z0 and z1 in eye space (z1 at B_zfar: the text's "B_znear" for z1 is a misprint).
std::pair<double, double> computeZ0Z1(const glm::dmat4& lightFrame, const Camera& camera, const glm::dvec3& eWorld, double bZnear,
                                      double bZfar);

// §9.2.4: the warp P with strength u = 1/n, followed by the axis swap that makes light-space y the
// depth (DESIGN §4); u → 0 is the uniform map, continuously.
glm::dmat4 computeWarp(double u, const glm::dvec3& eLs, double bZnear);

// Scale and translate so that the box fills [−1 + m, 1 − m] in x and y and [−1, 1] in z (m: the
// filter border, clipBorder).
glm::dmat4 fitToUnitCube(const Aabb& box, double borderXY);
double clipBorder(const ShadowInput& in);  // the border in clip units: 2 · borderTexels / mapSize

// An orthographic map fitted to the points in the given light frame.
glm::dmat4 fitUniform(const glm::dmat4& lightFrame, std::span<const glm::dvec3> points, double borderXY);

double angleDeg(const glm::dvec3& a, const glm::dvec3& b);

}  // namespace forest::shadows
