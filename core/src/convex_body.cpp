#include "forest/core/convex_body.hpp"

#include <glm/gtx/component_wise.hpp>

#include <algorithm>
#include <limits>
#include <array>
#include <cmath>
#include <map>
#include <span>

namespace forest {

std::pmr::memory_resource* convexBodyMemory() {
  // Never destroyed: bodies in static storage may outlive any other owner. Reserved up front: the
  // pool keeps what it is given back, and a frame's bodies hold at most a few hundred blocks of a
  // size (extrude's edge map has a node per edge), so once the reserve is handed back no frame asks
  // the heap for more — whatever its visible set, which with asynchronous queries differs from run
  // to run, so one walk as warm-up does not reach every high-water mark (DESIGN §9).
  static auto* const pool = [] {
    std::pmr::pool_options options;
    options.largest_required_pool_block = 64 * 1024;  // bodies' vertex lists reach a few KiB
    auto* p = new std::pmr::synchronized_pool_resource(options);
    std::vector<std::pair<void*, size_t>> reserve;
    // Sizes at least as fine as the pool's size classes (8-byte steps to 128, then coarser), so
    // every class up to 16 KiB gets blocks: about 3 MiB in all.
    for (size_t bytes = 8; bytes <= 16384; bytes += bytes < 128 ? 8 : bytes < 512 ? 64 : bytes / 2) {
      const int blocks = bytes <= 128 ? 512 : bytes <= 512 ? 256 : bytes <= 4096 ? 64 : 16;
      for (int k = 0; k < blocks; ++k) reserve.emplace_back(p->allocate(bytes), bytes);
    }
    for (const auto& [block, bytes] : reserve) p->deallocate(block, bytes);
    return p;
  }();
  return pool;
}

namespace {

using glm::dvec3;
using Points = std::pmr::vector<dvec3>;

bool lexLess(const dvec3& a, const dvec3& b) {
  if (a.x != b.x) return a.x < b.x;
  if (a.y != b.y) return a.y < b.y;
  return a.z < b.z;
}

struct LexLess {
  bool operator()(const dvec3& a, const dvec3& b) const { return lexLess(a, b); }
  bool operator()(const std::pair<dvec3, dvec3>& a, const std::pair<dvec3, dvec3>& b) const {
    if (a.first != b.first) return lexLess(a.first, b.first);
    return lexLess(a.second, b.second);
  }
};

// The point where edge a–b crosses the plane, computed from the lexicographically smaller end so
// that both polygons sharing the edge get the same bits.
dvec3 crossing(dvec3 a, double da, dvec3 b, double db) {
  if (lexLess(b, a)) {
    std::swap(a, b);
    std::swap(da, db);
  }
  const double t = da / (da - db);
  return a + t * (b - a);
}

dvec3 centroidOf(std::span<const dvec3> points) {
  dvec3 sum(0.0);
  for (const dvec3& p : points) sum += p;
  return points.empty() ? sum : sum / static_cast<double>(points.size());
}

// Removes exact duplicates, keeping the first occurrence order irrelevant.
// By value: callers move in, or copy with the pool explicitly (a pmr container copied plainly takes
// the default resource, the heap).
Points distinct(Points points) {
  std::sort(points.begin(), points.end(), lexLess);
  points.erase(std::unique(points.begin(), points.end()), points.end());
  return points;
}

// Orders coplanar points counter-clockwise about `normal`; empty if they span no area.
Polygon polygonFromCoplanarPoints(const Points& pointsIn, const dvec3& normal, double tolerance) {
  const Points points = distinct(Points(pointsIn, convexBodyMemory()));
  if (points.size() < 3) return Polygon(convexBodyMemory());
  const dvec3 c = centroidOf(points);
  const dvec3 helper = std::abs(normal.x) < 0.9 ? dvec3(1, 0, 0) : dvec3(0, 1, 0);
  const dvec3 u = glm::normalize(glm::cross(normal, helper));
  const dvec3 v = glm::cross(normal, u);
  std::pmr::vector<std::pair<double, dvec3>> byAngle(convexBodyMemory());
  for (const dvec3& p : points) byAngle.emplace_back(std::atan2(glm::dot(p - c, v), glm::dot(p - c, u)), p);
  std::sort(byAngle.begin(), byAngle.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  Polygon polygon(convexBodyMemory());
  for (const auto& [angle, p] : byAngle) polygon.push_back(p);
  // Twice the area must exceed a sliver of tolerance × size.
  dvec3 newell(0.0);
  for (size_t i = 0; i < polygon.size(); ++i) newell += glm::cross(polygon[i], polygon[(i + 1) % polygon.size()]);
  if (glm::length(newell) <= tolerance * tolerance) polygon.clear();
  return polygon;
}

// Reverses polygons whose normal points towards the body's centroid (convex bodies only).
void orientOutward(PolygonList& polygons) {
  Points all(convexBodyMemory());
  for (const Polygon& p : polygons) all.insert(all.end(), p.begin(), p.end());
  const dvec3 c = centroidOf(distinct(std::move(all)));
  for (Polygon& p : polygons) {
    if (glm::dot(polygonNormal(p), centroidOf(p) - c) < 0.0) std::reverse(p.begin(), p.end());
  }
}

void dropDegenerate(PolygonList& polygons) {
  for (Polygon& p : polygons) p.erase(std::unique(p.begin(), p.end()), p.end());
  for (Polygon& p : polygons) {
    if (p.size() > 1 && p.front() == p.back()) p.pop_back();
  }
  std::erase_if(polygons, [](const Polygon& p) { return p.size() < 3 || polygonNormal(p) == dvec3(0.0); });
}

// A flat body (one polygon) becomes two-sided so that every edge has a twin.
void makeTwoSidedIfFlat(PolygonList& polygons) {
  if (polygons.size() != 1) return;
  Polygon back(polygons[0].rbegin(), polygons[0].rend(), convexBodyMemory());
  polygons.push_back(std::move(back));
}

using EdgeOwners = std::pmr::map<std::pair<dvec3, dvec3>, size_t, LexLess>;

EdgeOwners directedEdges(const PolygonList& polygons) {
  EdgeOwners owners(convexBodyMemory());
  for (size_t i = 0; i < polygons.size(); ++i) {
    const Polygon& p = polygons[i];
    for (size_t k = 0; k < p.size(); ++k) owners[{p[k], p[(k + 1) % p.size()]}] = i;
  }
  return owners;
}

}  // namespace

dvec3 polygonNormal(const Polygon& polygon) {
  dvec3 n(0.0);
  const dvec3 c = centroidOf(polygon);  // relative to the centroid: exact far from the origin
  for (size_t i = 0; i < polygon.size(); ++i) {
    n += glm::cross(polygon[i] - c, polygon[(i + 1) % polygon.size()] - c);
  }
  const double length = glm::length(n);
  return length > 0.0 ? n / length : dvec3(0.0);
}

ConvexBody ConvexBody::fromCorners(const std::array<dvec3, 8>& c) {
  // Faces by corner index (bit 0 = x, bit 1 = y, bit 2 = z).
  constexpr int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  PolygonList polygons(convexBodyMemory());
  for (const auto& f : faces) polygons.emplace_back(std::initializer_list<dvec3>{c[f[0]], c[f[1]], c[f[2]], c[f[3]]});
  dropDegenerate(polygons);
  orientOutward(polygons);
  return ConvexBody(std::move(polygons));
}

ConvexBody ConvexBody::fromBox(const Aabb& box) {
  std::array<dvec3, 8> corners;
  for (int i = 0; i < 8; ++i) corners[i] = box.corner(i);
  ConvexBody body = fromCorners(corners);
  if (body.polygons_.empty() && box.valid()) {  // flat box: its largest face
    const dvec3 e = box.extent();
    Polygon face(convexBodyMemory());
    if (e.x > 0 && e.z > 0) face = {box.corner(0), box.corner(1), box.corner(5), box.corner(4)};
    else if (e.x > 0 && e.y > 0) face = {box.corner(0), box.corner(1), box.corner(3), box.corner(2)};
    else if (e.y > 0 && e.z > 0) face = {box.corner(0), box.corner(2), box.corner(6), box.corner(4)};
    if (!face.empty()) body.polygons_.push_back(face);
  }
  return body;
}

ConvexBody ConvexBody::fromInverseViewProjection(const glm::dmat4& inverseViewProjection) {
  std::array<dvec3, 8> corners;
  for (int i = 0; i < 8; ++i) {
    const glm::dvec4 ndc(i & 1 ? 1.0 : -1.0, i & 2 ? 1.0 : -1.0, i & 4 ? 1.0 : 0.0, 1.0);
    const glm::dvec4 world = inverseViewProjection * ndc;
    corners[i] = dvec3(world) / world.w;
  }
  return fromCorners(corners);
}

Points ConvexBody::vertices() const {
  Points all(convexBodyMemory());
  for (const Polygon& p : polygons_) all.insert(all.end(), p.begin(), p.end());
  return distinct(std::move(all));
}

Aabb ConvexBody::bounds() const {
  Aabb box;
  for (const Polygon& p : polygons_)
    for (const dvec3& v : p) box.extend(v);
  return box;
}

double ConvexBody::tolerance() const {
  const Aabb box = bounds();
  if (!box.valid()) return 0.0;
  const double magnitude = glm::compMax(glm::max(glm::abs(box.min), glm::abs(box.max)));
  return std::max(kRelativeTolerance * box.diagonal(), 64.0 * std::numeric_limits<double>::epsilon() * magnitude);
}

double ConvexBody::volume() const {
  if (polygons_.size() < 4) return 0.0;
  const dvec3 c = centroidOf(vertices());  // relative coordinates keep far-away bodies exact
  double sixVolume = 0.0;
  for (const Polygon& p : polygons_) {
    for (size_t i = 1; i + 1 < p.size(); ++i) sixVolume += glm::dot(p[0] - c, glm::cross(p[i] - c, p[i + 1] - c));
  }
  return sixVolume / 6.0;
}

bool ConvexBody::isClosed() const {
  if (polygons_.empty()) return false;
  const EdgeOwners owners = directedEdges(polygons_);
  for (const auto& [edge, polygon] : owners) {
    const auto twin = owners.find({edge.second, edge.first});
    if (twin == owners.end() || twin->second == polygon) return false;
  }
  return true;
}

bool ConvexBody::isFlat() const {
  if (polygons_.empty()) return false;
  const dvec3 n = polygonNormal(polygons_.front());
  const Plane plane = Plane::through(polygons_.front().front(), n);
  const double eps = tolerance();
  for (const dvec3& v : vertices()) {
    if (std::abs(plane.signedDistance(v)) > eps) return false;
  }
  return true;
}

// The tolerance of a clip is relative to the size of what is kept, not of what is cut away: a
// frustum 4e5 m long clipped to a 0.3 m thin scene box must not treat vertices 1e-4 m from the
// plane as on it (the thin result would be non-planar at 1e-3 of its size). `within` bounds the
// final result when the plane is one of several (a box's or a body's faces). Never below the
// rounding error of the input's coordinates.
double ConvexBody::clipTolerance(const Plane& plane, const Aabb& within) const {
  const Aabb box = bounds();
  const double magnitude = glm::compMax(glm::max(glm::abs(box.min), glm::abs(box.max)));
  const double roundingFloor = 64.0 * std::numeric_limits<double>::epsilon() * magnitude;
  Aabb kept;
  for (const Polygon& polygon : polygons_) {
    for (size_t i = 0; i < polygon.size(); ++i) {
      const dvec3& a = polygon[i];
      const dvec3& b = polygon[(i + 1) % polygon.size()];
      const double da = plane.signedDistance(a), db = plane.signedDistance(b);
      if (da <= 0.0) kept.extend(a);
      if ((da < 0.0 && db > 0.0) || (da > 0.0 && db < 0.0)) kept.extend(crossing(a, da, b, db));
    }
  }
  if (within.valid()) {
    kept.min = glm::max(kept.min, within.min);
    kept.max = glm::min(kept.max, within.max);
  }
  return kept.valid() ? std::max(kRelativeTolerance * kept.diagonal(), roundingFloor) : roundingFloor;
}

void ConvexBody::clip(const Plane& plane) { clipWithin(plane, Aabb{}); }

void ConvexBody::clipWithin(const Plane& plane, const Aabb& within) {
  if (polygons_.empty()) return;
  const double eps = clipTolerance(plane, within);
  // Vertices within eps of the plane are moved onto it (every polygon moves its copy the same
  // way), so the body lies in the half-space exactly: a later, tighter clip by the same plane
  // (a flat scene box) cannot cut it away.
  const double normalSquared = glm::dot(plane.normal, plane.normal);
  auto ontoPlane = [&](const dvec3& v, double distance) {
    return distance == 0.0 ? v : v - (distance / normalSquared) * plane.normal;
  };
  PolygonList kept(convexBodyMemory());
  Points onPlane(convexBodyMemory());
  std::pmr::vector<double> d(convexBodyMemory());
  for (const Polygon& polygon : polygons_) {
    d.assign(polygon.size(), 0.0);
    bool allOnPlane = true;
    for (size_t i = 0; i < polygon.size(); ++i) {
      d[i] = plane.signedDistance(polygon[i]);
      allOnPlane = allOnPlane && std::abs(d[i]) <= eps;
    }
    if (allOnPlane) {  // rebuilt as part of the cap
      for (size_t i = 0; i < polygon.size(); ++i) onPlane.push_back(ontoPlane(polygon[i], d[i]));
      continue;
    }
    Polygon clipped(convexBodyMemory());
    for (size_t i = 0; i < polygon.size(); ++i) {
      const size_t j = (i + 1) % polygon.size();
      if (std::abs(d[i]) <= eps) {
        const dvec3 v = ontoPlane(polygon[i], d[i]);
        clipped.push_back(v);
        onPlane.push_back(v);
      } else if (d[i] < 0.0) {
        clipped.push_back(polygon[i]);
      }
      if ((d[i] < -eps && d[j] > eps) || (d[i] > eps && d[j] < -eps)) {
        const dvec3 p = crossing(polygon[i], d[i], polygon[j], d[j]);
        clipped.push_back(p);
        onPlane.push_back(p);
      }
    }
    if (clipped.size() >= 3) kept.push_back(std::move(clipped));
  }
  dropDegenerate(kept);
  Polygon cap = polygonFromCoplanarPoints(onPlane, glm::normalize(plane.normal), eps);
  if (!cap.empty()) kept.push_back(std::move(cap));
  polygons_ = std::move(kept);
}

void ConvexBody::clip(const Aabb& box) {
  clipWithin(Plane{{-1, 0, 0}, box.min.x}, box);
  clipWithin(Plane{{1, 0, 0}, -box.max.x}, box);
  clipWithin(Plane{{0, -1, 0}, box.min.y}, box);
  clipWithin(Plane{{0, 1, 0}, -box.max.y}, box);
  clipWithin(Plane{{0, 0, -1}, box.min.z}, box);
  clipWithin(Plane{{0, 0, 1}, -box.max.z}, box);
}

void ConvexBody::clip(const ConvexBody& other) {
  if (other.polygons_.empty()) {
    polygons_.clear();
    return;
  }
  std::pmr::vector<Plane> planes(convexBodyMemory());  // copied first: `other` may be this body
  for (const Polygon& p : other.polygons_) planes.push_back(Plane::through(centroidOf(p), polygonNormal(p)));
  const Aabb within = other.bounds();
  for (const Plane& plane : planes) clipWithin(plane, within);
}

void ConvexBody::hullWithPoint(const dvec3& point) {
  if (polygons_.empty()) {
    return;
  }
  makeTwoSidedIfFlat(polygons_);
  const double eps = tolerance();
  std::pmr::vector<bool> sees(polygons_.size(), false, convexBodyMemory());
  bool any = false;
  for (size_t i = 0; i < polygons_.size(); ++i) {
    sees[i] = Plane::through(polygons_[i].front(), polygonNormal(polygons_[i])).signedDistance(point) > eps;
    any = any || sees[i];
  }
  if (!any) return;  // the point is inside
  const EdgeOwners owners = directedEdges(polygons_);
  PolygonList result(convexBodyMemory());
  for (size_t i = 0; i < polygons_.size(); ++i) {
    if (sees[i]) continue;
    const Polygon& p = polygons_[i];
    result.push_back(p);
    for (size_t k = 0; k < p.size(); ++k) {
      const dvec3& a = p[k];
      const dvec3& b = p[(k + 1) % p.size()];
      const auto twin = owners.find({b, a});
      if (twin == owners.end() || sees[twin->second]) result.emplace_back(std::initializer_list<dvec3>{a, b, point});
    }
  }
  dropDegenerate(result);
  orientOutward(result);
  polygons_ = std::move(result);
}

void ConvexBody::extrude(const dvec3& direction, const Aabb& until) {
  if (polygons_.empty() || glm::length(direction) == 0.0) return;
  const dvec3 d = glm::normalize(direction);
  Aabb reach = bounds();
  if (until.valid()) reach.extend(until);
  const dvec3 offset = (2.0 * reach.diagonal() + 1.0) * d;

  makeTwoSidedIfFlat(polygons_);
  std::pmr::vector<bool> facing(polygons_.size(), false, convexBodyMemory());
  for (size_t i = 0; i < polygons_.size(); ++i) facing[i] = glm::dot(polygonNormal(polygons_[i]), d) > 1e-12;
  const EdgeOwners owners = directedEdges(polygons_);
  PolygonList result(convexBodyMemory());
  for (size_t i = 0; i < polygons_.size(); ++i) {
    Polygon p(polygons_[i], convexBodyMemory());
    for (size_t k = 0; k < p.size(); ++k) {
      const dvec3& a = p[k];
      const dvec3& b = p[(k + 1) % p.size()];
      const auto twin = owners.find({b, a});
      // A silhouette edge (one side facing, one not) becomes a quad along the sweep; an edge
      // without a twin is treated as silhouette so that no hole is left.
      const bool silhouette = twin == owners.end() ? true : (facing[i] != facing[twin->second]);
      if (silhouette && (!facing[i] || twin == owners.end()))
        result.emplace_back(std::initializer_list<dvec3>{a, b, b + offset, a + offset});
    }
    if (facing[i]) {
      for (dvec3& v : p) v += offset;
    }
    result.push_back(std::move(p));
  }
  dropDegenerate(result);
  orientOutward(result);
  polygons_ = std::move(result);
}

ConvexBody ConvexBody::transformed(const glm::dmat4& m) const {
  PolygonList out(polygons_, convexBodyMemory());
  for (Polygon& p : out) {
    for (dvec3& v : p) {
      const glm::dvec4 h = m * glm::dvec4(v, 1.0);
      v = dvec3(h) / h.w;
    }
  }
  return ConvexBody(std::move(out));
}

}  // namespace forest
