#pragma once
// Plane polygons: convex hull and area.
#include <glm/glm.hpp>

#include <span>
#include <vector>

namespace forest {

// Andrew's monotone chain: counter-clockwise (y up), no collinear or repeated points.
std::vector<glm::dvec2> convexHull(std::vector<glm::dvec2> points);
// The same without allocating: sorts `points` in place and writes the hull's points to the front of
// `hull` (room for 2 · points.size()); returns how many. Fewer than 3 distinct points: those points.
size_t convexHullInPlace(std::span<glm::dvec2> points, std::span<glm::dvec2> hull);
// Area of a simple polygon (shoelace), either orientation.
double polygonArea(const std::vector<glm::dvec2>& polygon);

}  // namespace forest
