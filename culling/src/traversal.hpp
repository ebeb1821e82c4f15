#pragma once
// One culling frame's shared state and the helpers every traversal strategy uses (internal).
#include <glm/glm.hpp>

#include <cmath>
#include <limits>
#include <span>
#include <utility>
#include <vector>

#include "forest/core/frustum.hpp"
#include "forest/culling/occlusion_culler.hpp"

namespace forest::culling {

// Query results are collected at batch boundaries, every kBatchSteps traversal steps: the queries
// issued before the previous boundary are taken (waiting if need be), the newer ones stay pending
// while traversal and drawing go on. Taking results at fixed points, not whenever the driver
// happens to have them, makes the traversal — and so the visible set, z_f and the shadows —
// identical from run to run; polling for availability would also flush llvmpipe's command stream.
constexpr int kBatchSteps = 64;

// Eye-space depth range of a box's corners.
inline std::pair<double, double> depthRange(const Aabb& box, const glm::dmat4& view) {
  double nearest = std::numeric_limits<double>::infinity(), farthest = -nearest;
  for (int c = 0; c < 8; ++c) {
    const double depth = -(view * glm::dvec4(box.corner(c), 1.0)).z;
    nearest = std::min(nearest, depth);
    farthest = std::max(farthest, depth);
  }
  return {nearest, farthest};
}

inline double distanceToBox(const Aabb& box, const glm::dvec3& p) {
  return glm::length(glm::max(glm::max(box.min - p, p - box.max), glm::dvec3(0.0)));
}

// Traversal queue entry: nearest first.
struct Entry {
  double distance;
  std::int32_t node;
  bool operator<(const Entry& other) const { return distance > other.distance; }
};

struct OcclusionCuller::Traversal {
  const Bvh& bvh;
  const Camera& camera;
  glm::dmat4 view;
  Frustum frustum;
  ObjectDrawer& drawer;
  CullingStats& stats;
  std::vector<std::uint32_t> visible;  // objects of the leaves found visible (may repeat)

  const std::vector<BvhNode>& nodes() const { return bvh.nodes(); }
  std::span<const std::uint32_t> objectsOf(std::int32_t n) const {
    const BvhNode& node = bvh.nodes()[n];
    return {bvh.objects().data() + node.first, node.count};
  }
  void markVisible(std::int32_t n) {
    const auto objects = objectsOf(n);
    visible.insert(visible.end(), objects.begin(), objects.end());
  }
  Entry entry(std::int32_t n) const { return {distanceToBox(bvh.nodes()[n].bounds, camera.position), n}; }
  // Visible without a query: the box holds the eye (grown by z_n) or reaches in front of the near
  // plane, where its rasterised faces would be clipped away.
  bool visibleWithoutQuery(std::int32_t n) const {
    const Aabb& box = bvh.nodes()[n].bounds;
    const Aabb grown{box.min - glm::dvec3(camera.near), box.max + glm::dvec3(camera.near)};
    if (grown.contains(camera.position)) return true;
    return depthRange(box, view).first <= camera.near;
  }
};

}  // namespace forest::culling
