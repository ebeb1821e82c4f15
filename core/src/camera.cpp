#include "forest/core/camera.hpp"

#include <glm/gtc/matrix_transform.hpp>

namespace forest {

glm::dvec3 directionFromYawPitch(double yaw, double pitch) {
  // R_y(yaw) · R_x(pitch) · (0, 0, −1)
  return {-std::sin(yaw) * std::cos(pitch), std::sin(pitch), -std::cos(yaw) * std::cos(pitch)};
}

glm::dvec3 Camera::forward() const { return directionFromYawPitch(yaw, pitch); }

glm::dmat4 Camera::view() const {
  // Rotation is R_y(yaw)·R_x(pitch); the view matrix is its inverse after the translation.
  // Built from angles, not lookAt, so looking straight up or down stays well defined.
  const glm::dmat4 rotation = glm::rotate(glm::rotate(glm::dmat4(1.0), yaw, {0.0, 1.0, 0.0}), pitch,
                                          glm::dvec3(1.0, 0.0, 0.0));
  return glm::transpose(rotation) * glm::translate(glm::dmat4(1.0), -position);
}

glm::dmat4 Camera::projection() const {
  // Reversed-Z: the zero-to-one perspective with near and far swapped maps z_eye = −near to 1
  // and z_eye = −far to 0.
  return glm::perspectiveRH_ZO(fovy, aspect, far, near);
}

}  // namespace forest
