#pragma once
// Convex polyhedra as lists of convex polygons (thesis §9.2.2): built from a box or from a
// frustum's inverse view-projection, clipped by planes, boxes and other bodies (holes closed),
// hulled with a point, extruded along a direction up to a box. Empty and flat results are
// represented: an empty body has no polygons; a flat one is a single polygon.
//
// Tolerances are relative to the body (kRelativeTolerance × its size, but never below the
// rounding error of its coordinates), so a body far from the origin or very small behaves the same.
// Intersection points are computed from the lexicographically smaller endpoint of an edge, so the
// two polygons sharing an edge get bit-identical vertices and the topology stays exact.
//
// Storage: every body, and the temporaries of its operations, take their memory from one pool
// (convexBodyMemory()), so a frame that builds and clips bodies — the focus body, the receivers'
// parts inside the view — reuses the blocks the last frame gave back instead of allocating
// (DESIGN §9: no heap allocation in a steady-state frame).
#include <glm/glm.hpp>

#include <array>
#include <memory_resource>
#include <vector>

#include "forest/core/bounds.hpp"

namespace forest {

// The pool (std::pmr::synchronized_pool_resource: thread-safe; it keeps what it was given back).
std::pmr::memory_resource* convexBodyMemory();

using Polygon = std::pmr::vector<glm::dvec3>;  // convex, counter-clockwise seen from outside
using PolygonList = std::pmr::vector<Polygon>;

class ConvexBody {
 public:
  static constexpr double kRelativeTolerance = 1e-9;

  ConvexBody() : polygons_(convexBodyMemory()) {}
  explicit ConvexBody(const PolygonList& polygons) : polygons_(polygons, convexBodyMemory()) {}
  explicit ConvexBody(PolygonList&& polygons) : polygons_(std::move(polygons), convexBodyMemory()) {}
  // Copies take their storage from the pool too (a pmr container's copy would use the default one).
  ConvexBody(const ConvexBody& other) : polygons_(other.polygons_, convexBodyMemory()) {}
  ConvexBody(ConvexBody&&) noexcept = default;
  ConvexBody& operator=(const ConvexBody&) = default;
  ConvexBody& operator=(ConvexBody&&) noexcept = default;

  static ConvexBody fromBox(const Aabb& box);
  // The 8 corners: bit 0 selects x, bit 1 y, bit 2 z (0 = low, 1 = high), any orientation.
  static ConvexBody fromCorners(const std::array<glm::dvec3, 8>& corners);
  // A view frustum in world space from inverse(projection · view), for the engine's clip
  // convention: NDC x, y ∈ [−1, 1], z ∈ [0, 1].
  static ConvexBody fromInverseViewProjection(const glm::dmat4& inverseViewProjection);

  const PolygonList& polygons() const { return polygons_; }
  bool empty() const { return polygons_.empty(); }
  // Distinct vertices (exact duplicates removed), in pool storage.
  std::pmr::vector<glm::dvec3> vertices() const;
  Aabb bounds() const;
  // The comparison tolerance for this body (world units).
  double tolerance() const;
  // Enclosed volume (divergence theorem over the faces); 0 for empty and flat bodies.
  double volume() const;
  // True when every directed edge has its reverse in another polygon (a closed 2-manifold).
  bool isClosed() const;
  // True when every vertex lies within tolerance of one plane (a polygon, a segment or a point).
  bool isFlat() const;

  // Keeps the part with plane.signedDistance ≤ 0 and closes the hole with a polygon on the plane.
  void clip(const Plane& plane);
  void clip(const Aabb& box);
  // Intersection with another convex body (clipped by each of its face planes).
  void clip(const ConvexBody& other);
  // Convex hull of the body and a point (thesis convexHullWithPoint): faces that see the point
  // are removed and the silhouette is joined to the point with triangles.
  void hullWithPoint(const glm::dvec3& point);
  // Sweeps the body along `direction` until it has left `until` (thesis
  // convexHullWithDirection): faces facing `direction` move, silhouette edges become quads.
  // Clip by `until` afterwards to keep the part inside.
  void extrude(const glm::dvec3& direction, const Aabb& until);

  // Every vertex through a homogeneous transform (divided by w; w must stay positive).
  ConvexBody transformed(const glm::dmat4& m) const;

 private:
  double clipTolerance(const Plane& plane, const Aabb& within) const;
  void clipWithin(const Plane& plane, const Aabb& within);
  PolygonList polygons_;
};

// Outward unit normal of a convex polygon (Newell's method); zero for a degenerate polygon.
glm::dvec3 polygonNormal(const Polygon& polygon);

}  // namespace forest
