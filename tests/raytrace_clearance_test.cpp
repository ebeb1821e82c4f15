// raytrace::cameraClearance against a closed cube, with the distances where the verdict must change
// derived from the camera: a face straight ahead cuts the near plane when nearer than z_n; a face
// beside the view direction when nearer than the near rectangle's half-width z_n·tan(fovy/2)·aspect.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "forest/core/camera.hpp"
#include "forest/raytrace/clearance.hpp"
#include "forest/raytrace/ray_scene.hpp"

namespace forest {
namespace {

constexpr std::uint32_t kCube = 7;

// The cube [−1, 1]³, its triangles counter-clockwise seen from outside.
void addCube(raytrace::RayScene& scene) {
  std::vector<glm::vec3> corners;
  for (int i = 0; i < 8; ++i) corners.emplace_back((i & 1) ? 1.0f : -1.0f, (i & 2) ? 1.0f : -1.0f, (i & 4) ? 1.0f : -1.0f);
  const std::vector<std::uint32_t> indices{0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
                                           2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
  scene.addInstance(scene.addMesh(corners, indices), glm::dmat4(1.0), kCube);
  scene.commit();
}

Camera cameraAt(glm::dvec3 position, double yawDeg) {
  Camera c;
  c.position = position;
  c.yaw = glm::radians(yawDeg);
  c.pitch = 0.0;
  c.near = 0.2;
  c.fovy = glm::radians(60.0);
  c.aspect = 16.0 / 9.0;
  return c;
}

TEST(CameraClearance, TheEyeInsideAClosedMeshIsFound) {
  raytrace::RayScene scene;
  addCube(scene);
  for (const glm::dvec3& eye : {glm::dvec3(0.0), glm::dvec3(0.9, -0.8, 0.5)}) {
    const raytrace::Clearance c = raytrace::cameraClearance(scene, cameraAt(eye, 30.0));
    EXPECT_FALSE(c.clear);
    EXPECT_EQ(c.objectId, kCube);
    EXPECT_EQ(c.what, "the eye is inside");
  }
}

TEST(CameraClearance, AFaceCutsTheNearPlaneExactlyWithinItsReach) {
  raytrace::RayScene scene;
  addCube(scene);
  const Camera probe = cameraAt(glm::dvec3(0.0), 0.0);
  ASSERT_NEAR(probe.forward().z, -1.0, 1e-12);  // yaw 0 looks along −z
  const double zn = probe.near, halfWidth = zn * std::tan(0.5 * probe.fovy) * probe.aspect;  // 0.2, 0.205
  // Straight ahead: the face z = 1 at distance d in front of the eye.
  for (const double d : {0.5 * zn, 0.95 * zn}) {
    const raytrace::Clearance c = raytrace::cameraClearance(scene, cameraAt({0.0, 0.0, 1.0 + d}, 0.0));
    EXPECT_FALSE(c.clear) << d;
    EXPECT_EQ(c.what, "it cuts the near plane") << d;
  }
  EXPECT_TRUE(raytrace::cameraClearance(scene, cameraAt({0.0, 0.0, 1.0 + 1.05 * zn}, 0.0)).clear);
  EXPECT_TRUE(raytrace::cameraClearance(scene, cameraAt({0.0, 0.0, 1.0 + 0.5 * zn}, 180.0)).clear);  // looking away
  // Beside the view: the face x = 1 parallel to it, the eye d to its right, looking along −z.
  EXPECT_FALSE(raytrace::cameraClearance(scene, cameraAt({1.0 + 0.9 * halfWidth, 0.0, 0.0}, 0.0)).clear);
  EXPECT_TRUE(raytrace::cameraClearance(scene, cameraAt({1.0 + 1.1 * halfWidth, 0.0, 0.0}, 0.0)).clear);
}

}  // namespace
}  // namespace forest
