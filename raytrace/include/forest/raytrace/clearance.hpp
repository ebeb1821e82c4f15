#pragma once
// Whether a camera keeps clear of the closed meshes it looks at (trunks, crowns, props): an eye
// inside one, or geometry between the eye and the near plane's rectangle, shows the inside of a
// mesh or clips it open. A walkthrough's camera must keep clear in every frame.
#include <cstdint>
#include <string>

#include "forest/core/camera.hpp"
#include "forest/raytrace/ray_scene.hpp"

namespace forest::raytrace {

struct Clearance {
  bool clear = true;
  std::uint32_t objectId = kNoObject;  // the object in the way
  std::string what;                    // "the eye is inside" or "it cuts the near plane"
};

// Checked with rays: the eye is inside a closed mesh when the nearest surface along at least four of
// the six axis directions is one object's, seen from behind (counter-clockwise winding faces outward); the near plane is cut
// when a surface crosses a segment from the eye to a point of the near rectangle (its corners,
// edge midpoints and centre) or a segment across the rectangle (its edges, diagonals and the lines
// between the edge midpoints). A surface that passes between those segments without touching any
// is missed: the segments lie at most half the rectangle's width apart (a few millimetres).
Clearance cameraClearance(const RayScene& scene, const Camera& camera);

}  // namespace forest::raytrace
