// Camera conventions: yaw/pitch directions, reversed-Z zero-to-one depth.
#include <gtest/gtest.h>

#include "forest/core/camera.hpp"
#include "forest/core/error.hpp"

namespace forest {
namespace {

glm::dvec3 project(const Camera& c, const glm::dvec3& world) {
  const glm::dvec4 clip = c.projection() * c.view() * glm::dvec4(world, 1.0);
  return glm::dvec3(clip) / clip.w;
}

TEST(Camera, YawZeroLooksDownNegativeZAndPositiveYawTurnsLeft) {
  EXPECT_NEAR(glm::distance(directionFromYawPitch(0, 0), glm::dvec3(0, 0, -1)), 0.0, 1e-15);
  EXPECT_NEAR(glm::distance(directionFromYawPitch(glm::radians(90.0), 0), glm::dvec3(-1, 0, 0)), 0.0, 1e-15);
  EXPECT_NEAR(glm::distance(directionFromYawPitch(0, glm::radians(90.0)), glm::dvec3(0, 1, 0)), 0.0, 1e-15);
}

TEST(Camera, ReversedZMapsNearToOneAndFarToZero) {
  Camera c;
  c.position = {10, 5, -3};
  c.yaw = 0.7;
  c.pitch = -0.3;
  c.near = 0.1;
  c.far = 70.0;
  const glm::dvec3 f = c.forward();
  EXPECT_NEAR(project(c, c.position + c.near * f).z, 1.0, 1e-12);
  EXPECT_NEAR(project(c, c.position + c.far * f).z, 0.0, 1e-12);
  const glm::dvec3 centre = project(c, c.position + 5.0 * f);
  EXPECT_NEAR(centre.x, 0.0, 1e-12);
  EXPECT_NEAR(centre.y, 0.0, 1e-12);
}

TEST(Camera, StraightDownStaysWellDefined) {
  Camera c;
  c.pitch = -glm::radians(90.0);
  const glm::dmat4 v = c.view();
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) EXPECT_TRUE(std::isfinite(v[i][j]));
  EXPECT_NEAR(project(c, c.position + glm::dvec3(0, -1, 0)).x, 0.0, 1e-12);
}

TEST(Camera, OrientReproducesViewDirectionAndUp) {
  struct Case {
    glm::dvec3 view, up;
  };
  // Level, rolled, straight down and straight up (yaw free), unnormalised inputs.
  for (const Case& k : {Case{{1, -0.2, 0.3}, {0, 1, 0}}, Case{{0, 0, -1}, {1, 1, 0}}, Case{{0, -3, 0}, {0, 0, 1}},
                        Case{{0, 2, 0}, {-1, 0, 0}}, Case{{0.3, 0.9, -0.1}, {0.2, -1, 0.5}}}) {
    Camera c;
    c.orient(k.view, k.up);
    EXPECT_NEAR(glm::distance(c.forward(), glm::normalize(k.view)), 0.0, 1e-12);
    const glm::dvec3 f = glm::normalize(k.view);
    const glm::dvec3 upPerpendicular = glm::normalize(k.up - glm::dot(k.up, f) * f);
    EXPECT_NEAR(glm::distance(c.up(), upPerpendicular), 0.0, 1e-12);
    // The image's up is +y in clip space.
    const glm::dvec3 above = project(c, c.position + 5.0 * f + 0.1 * upPerpendicular);
    EXPECT_NEAR(above.x, 0.0, 1e-9);
    EXPECT_GT(above.y, 0.0);
  }
  Camera c;
  EXPECT_THROW(c.orient({0, 0, 0}, {0, 1, 0}), InputError);
  EXPECT_THROW(c.orient({0, 1, 0}, {0, 2, 0}), InputError);
}

}  // namespace
}  // namespace forest
