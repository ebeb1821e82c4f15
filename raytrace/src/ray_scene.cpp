#include "forest/raytrace/ray_scene.hpp"

#include <embree3/rtcore.h>
#include <fmt/format.h>

#include <cstring>
#include <unordered_map>
#include <vector>

#include "forest/core/error.hpp"

namespace forest::raytrace {

struct RayScene::Impl {
  RTCDevice device = nullptr;
  RTCScene top = nullptr;
  std::vector<RTCScene> meshes;               // one scene per mesh, instanced into `top`
  std::vector<std::uint32_t> instanceObject;  // object ID per instance geometry ID
  std::vector<std::uint32_t> instanceMesh;    // mesh per instance geometry ID
  std::vector<glm::dmat3> instanceNormal;     // object → world for normals (inverse transpose)
  std::vector<std::size_t> meshTriangles;
  std::unordered_map<std::uint32_t, std::size_t> objectTriangles;
  bool committed = false;
};

namespace {

void check(RTCDevice device, const char* what) {
  const RTCError error = rtcGetDeviceError(device);
  if (error != RTC_ERROR_NONE) throw Error(fmt::format("Embree: {} failed (error {})", what, static_cast<int>(error)));
}

}  // namespace

RayScene::RayScene() : impl_(std::make_unique<Impl>()) {
  impl_->device = rtcNewDevice(nullptr);
  if (!impl_->device) throw Error("Embree: cannot create a device");
  impl_->top = rtcNewScene(impl_->device);
  rtcSetSceneFlags(impl_->top, RTC_SCENE_FLAG_ROBUST);
  check(impl_->device, "rtcNewScene");
}

RayScene::~RayScene() {
  for (RTCScene s : impl_->meshes) rtcReleaseScene(s);
  if (impl_->top) rtcReleaseScene(impl_->top);
  if (impl_->device) rtcReleaseDevice(impl_->device);
}

std::uint32_t RayScene::addMesh(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices) {
  if (indices.size() % 3 != 0) throw Error("RayScene::addMesh: index count is not a multiple of 3");
  RTCScene scene = rtcNewScene(impl_->device);
  rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);  // watertight: no ray slips between two triangles
  RTCGeometry geometry = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                               3 * sizeof(float), positions.size()));
  auto* triangles = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                   3 * sizeof(unsigned), indices.size() / 3));
  check(impl_->device, "rtcSetNewGeometryBuffer");
  std::memcpy(vertices, positions.data(), positions.size() * sizeof(glm::vec3));
  std::memcpy(triangles, indices.data(), indices.size() * sizeof(std::uint32_t));
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(scene, geometry);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(scene);
  check(impl_->device, "mesh commit");
  impl_->meshes.push_back(scene);
  impl_->meshTriangles.push_back(indices.size() / 3);
  return static_cast<std::uint32_t>(impl_->meshes.size() - 1);
}

void RayScene::addInstance(std::uint32_t mesh, const glm::dmat4& objectToWorld, std::uint32_t objectId) {
  if (mesh >= impl_->meshes.size()) throw Error("RayScene::addInstance: no such mesh");
  RTCGeometry instance = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_INSTANCE);
  rtcSetGeometryInstancedScene(instance, impl_->meshes[mesh]);
  const glm::mat4 m(objectToWorld);
  rtcSetGeometryTransform(instance, 0, RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR, &m[0][0]);
  rtcCommitGeometry(instance);
  const unsigned id = rtcAttachGeometry(impl_->top, instance);
  rtcReleaseGeometry(instance);
  check(impl_->device, "instance");
  if (impl_->instanceObject.size() <= id) {
    impl_->instanceObject.resize(id + 1, kNoObject);
    impl_->instanceMesh.resize(id + 1, 0);
    impl_->instanceNormal.resize(id + 1, glm::dmat3(1.0));
  }
  impl_->instanceNormal[id] = glm::transpose(glm::inverse(glm::dmat3(objectToWorld)));
  impl_->objectTriangles[objectId] += impl_->meshTriangles[mesh];
  impl_->instanceObject[id] = objectId;
  impl_->instanceMesh[id] = mesh;
  impl_->committed = false;
}

void RayScene::commit() {
  rtcCommitScene(impl_->top);
  check(impl_->device, "rtcCommitScene");
  impl_->committed = true;
}

RayHit RayScene::intersect(const glm::dvec3& origin, const glm::dvec3& direction, double tNear, double tFar) const {
  if (!impl_->committed) throw Error("RayScene::intersect before commit()");
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit ray{};
  ray.ray.org_x = static_cast<float>(origin.x);
  ray.ray.org_y = static_cast<float>(origin.y);
  ray.ray.org_z = static_cast<float>(origin.z);
  ray.ray.dir_x = static_cast<float>(direction.x);
  ray.ray.dir_y = static_cast<float>(direction.y);
  ray.ray.dir_z = static_cast<float>(direction.z);
  ray.ray.tnear = static_cast<float>(tNear);
  ray.ray.tfar = tFar > 3e38 ? std::numeric_limits<float>::infinity() : static_cast<float>(tFar);
  ray.ray.mask = 0xffffffffu;
  ray.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  ray.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(impl_->top, &context, &ray);
  RayHit hit;
  if (ray.hit.geomID == RTC_INVALID_GEOMETRY_ID) return hit;
  hit.hit = true;
  hit.distance = ray.ray.tfar;
  hit.primitive = ray.hit.primID;
  hit.u = ray.hit.u;
  hit.v = ray.hit.v;
  const unsigned instance = ray.hit.instID[0];
  if (instance < impl_->instanceObject.size()) {
    hit.objectId = impl_->instanceObject[instance];
    hit.mesh = impl_->instanceMesh[instance];
    // Embree reports Ng in the instanced mesh's own space.
    const glm::dvec3 n = impl_->instanceNormal[instance] * glm::dvec3(ray.hit.Ng_x, ray.hit.Ng_y, ray.hit.Ng_z);
    if (glm::length(n) > 0.0) hit.normal = glm::normalize(n);
  }
  return hit;
}

bool RayScene::occluded(const glm::dvec3& origin, const glm::dvec3& direction, double tNear, double tFar) const {
  if (!impl_->committed) throw Error("RayScene::occluded before commit()");
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay ray{};
  ray.org_x = static_cast<float>(origin.x);
  ray.org_y = static_cast<float>(origin.y);
  ray.org_z = static_cast<float>(origin.z);
  ray.dir_x = static_cast<float>(direction.x);
  ray.dir_y = static_cast<float>(direction.y);
  ray.dir_z = static_cast<float>(direction.z);
  ray.tnear = static_cast<float>(tNear);
  ray.tfar = tFar > 3e38 ? std::numeric_limits<float>::infinity() : static_cast<float>(tFar);
  ray.mask = 0xffffffffu;
  rtcOccluded1(impl_->top, &context, &ray);
  return ray.tfar < 0.0f;  // Embree sets tfar to −∞ on a hit
}

std::size_t RayScene::triangles(std::uint32_t objectId) const {
  const auto it = impl_->objectTriangles.find(objectId);
  return it == impl_->objectTriangles.end() ? 0 : it->second;
}

}  // namespace forest::raytrace
