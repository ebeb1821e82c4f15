#pragma once
// A CPU ray-traced mirror of the scene with Embree 3: triangle meshes placed by instances, each
// instance carrying the object ID the GPU writes, so primary-ray ID images and shadow rays can be
// compared with what the renderer draws (ground truth; DESIGN §5).
#include <glm/glm.hpp>

#include <cstdint>
#include <limits>
#include <memory>
#include <span>

namespace forest::raytrace {

constexpr std::uint32_t kNoObject = std::numeric_limits<std::uint32_t>::max();

struct RayHit {
  bool hit = false;
  double distance = 0.0;       // along the (unit) direction
  std::uint32_t objectId = kNoObject;
  std::uint32_t primitive = 0; // triangle index within the mesh
  std::uint32_t mesh = 0;      // the mesh (prototype) hit
  double u = 0.0, v = 0.0;     // barycentric coordinates of the hit in the triangle (Embree's)
  glm::dvec3 normal{0.0};      // geometric normal in the world (unit; the triangle's winding side)
};

class RayScene {
 public:
  RayScene();
  ~RayScene();
  RayScene(const RayScene&) = delete;
  RayScene& operator=(const RayScene&) = delete;

  // A mesh in its own space (float positions, triangle indices); returns its handle.
  std::uint32_t addMesh(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices);
  // Places a mesh with an object-to-world transform; hits report `objectId`.
  void addInstance(std::uint32_t mesh, const glm::dmat4& objectToWorld, std::uint32_t objectId);
  // Builds the acceleration structures; call after the last add, before tracing.
  void commit();

  // Closest hit with distance in (tNear, tFar). `direction` must be unit length.
  RayHit intersect(const glm::dvec3& origin, const glm::dvec3& direction, double tNear = 0.0,
                   double tFar = std::numeric_limits<double>::infinity()) const;
  // Whether anything lies on the ray within (tNear, tFar) (any hit; faster than intersect).
  bool occluded(const glm::dvec3& origin, const glm::dvec3& direction, double tNear = 0.0,
                double tFar = std::numeric_limits<double>::infinity()) const;
  // Triangles of the instances carrying `objectId` (0 when none).
  std::size_t triangles(std::uint32_t objectId) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace forest::raytrace
