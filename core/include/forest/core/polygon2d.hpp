#pragma once
// Plane polygons: convex hull and area.
#include <glm/glm.hpp>

#include <vector>

namespace forest {

// Andrew's monotone chain: counter-clockwise (y up), no collinear or repeated points.
std::vector<glm::dvec2> convexHull(std::vector<glm::dvec2> points);
// Area of a simple polygon (shoelace), either orientation.
double polygonArea(const std::vector<glm::dvec2>& polygon);

}  // namespace forest
