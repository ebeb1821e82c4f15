#pragma once
// The eye camera, in double precision. Conventions (DESIGN §6, §4 clip control):
// right-handed world, y up; yaw 0 looks along −z, positive yaw turns left (counter-clockwise seen
// from above); pitch positive looks up. The engine's one depth convention is reversed-Z with a
// zero-to-one clip range (glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE)): depth 1 at the near plane,
// 0 at the far plane, and a GL_GREATER depth test.
#include <glm/glm.hpp>

namespace forest {

struct Camera {
  glm::dvec3 position{0.0};
  double yaw = 0.0;    // radians
  double pitch = 0.0;  // radians, within [−π/2, π/2]
  double roll = 0.0;   // radians about the view axis; positive turns the image clockwise
  double fovy = glm::radians(60.0);  // vertical field of view, radians
  double aspect = 16.0 / 9.0;        // width / height
  double near = 0.1;
  double far = 70.0;

  // Unit view direction, and the image's up and right directions in the world.
  glm::dvec3 forward() const;
  glm::dvec3 up() const;
  glm::dvec3 right() const;
  // World-from-camera rotation R_y(yaw) · R_x(pitch) · R_z(roll).
  glm::dmat4 rotation() const;
  // Sets yaw, pitch and roll so that the camera looks along `viewDirection` with the image's up
  // as close to `upHint` as possible (neither needs to be unit). Throws InputError when either is
  // zero or not finite, or when they are parallel.
  void orient(const glm::dvec3& viewDirection, const glm::dvec3& upHint);
  // World → eye (right-handed, eye looks along −z).
  glm::dmat4 view() const;
  // Eye → clip, reversed-Z, zero-to-one depth.
  glm::dmat4 projection() const;
  // The eye depth (metres) of a reversed-Z depth-buffer value d in (0, 1] of this camera: n f / (n + d (f − n)).
  double eyeDepthOfReversedZ(double d) const { return near * far / (near + d * (far - near)); }
};

// Unit direction for a yaw/pitch pair (radians), with the conventions above.
glm::dvec3 directionFromYawPitch(double yaw, double pitch);

}  // namespace forest
