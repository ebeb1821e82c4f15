#include "forest/core/camera.hpp"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>

#include "forest/core/error.hpp"

namespace forest {

glm::dvec3 directionFromYawPitch(double yaw, double pitch) {
  // R_y(yaw) · R_x(pitch) · (0, 0, −1)
  return {-std::sin(yaw) * std::cos(pitch), std::sin(pitch), -std::cos(yaw) * std::cos(pitch)};
}

glm::dmat4 Camera::rotation() const {
  const glm::dmat4 yawPitch =
      glm::rotate(glm::rotate(glm::dmat4(1.0), yaw, {0.0, 1.0, 0.0}), pitch, glm::dvec3(1.0, 0.0, 0.0));
  return roll == 0.0 ? yawPitch : glm::rotate(yawPitch, roll, glm::dvec3(0.0, 0.0, 1.0));
}

glm::dvec3 Camera::forward() const { return directionFromYawPitch(yaw, pitch); }
glm::dvec3 Camera::up() const { return glm::dvec3(rotation()[1]); }
glm::dvec3 Camera::right() const { return glm::dvec3(rotation()[0]); }

glm::dmat4 Camera::view() const {
  // The view matrix is the inverse rotation after the translation. Built from angles, not
  // lookAt, so looking straight up or down stays well defined.
  return glm::transpose(rotation()) * glm::translate(glm::dmat4(1.0), -position);
}

void Camera::orient(const glm::dvec3& viewDirection, const glm::dvec3& upHint) {
  const double viewLength = glm::length(viewDirection), upLength = glm::length(upHint);
  if (!std::isfinite(viewLength) || viewLength == 0.0) throw InputError("view direction: expected a finite non-zero vector");
  if (!std::isfinite(upLength) || upLength == 0.0) throw InputError("up vector: expected a finite non-zero vector");
  const glm::dvec3 f = viewDirection / viewLength;
  const glm::dvec3 upPerpendicular = upHint / upLength - glm::dot(upHint / upLength, f) * f;
  if (glm::length(upPerpendicular) < 1e-9) throw InputError("up vector: expected a direction not parallel to the view direction");
  pitch = std::asin(std::clamp(f.y, -1.0, 1.0));
  // Straight up or down the yaw is free: take the one that needs no roll.
  const double horizontal = std::hypot(f.x, f.z);
  yaw = horizontal > 1e-12 ? std::atan2(-f.x, -f.z)
                           : (f.y < 0.0 ? std::atan2(-upPerpendicular.x, -upPerpendicular.z)
                                        : std::atan2(upPerpendicular.x, upPerpendicular.z));
  roll = 0.0;
  // Camera up after roll = cos(roll)·up₀ − sin(roll)·right₀ (R_z applied first).
  const glm::dvec3 up0 = up(), right0 = right();
  roll = std::atan2(-glm::dot(upPerpendicular, right0), glm::dot(upPerpendicular, up0));
  if (std::abs(roll) < 1e-15) roll = 0.0;
}

glm::dmat4 Camera::projection() const {
  // Reversed-Z: the zero-to-one perspective with near and far swapped maps z_eye = −near to 1
  // and z_eye = −far to 0.
  return glm::perspectiveRH_ZO(fovy, aspect, far, near);
}

}  // namespace forest
