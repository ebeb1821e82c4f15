// The camera paths of forest bench culling (bench_paths.hpp) and of the stress run (walkPath).
#include "bench_paths.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include <fmt/format.h>

#include "commands.hpp"

namespace forest::app {

namespace {

// How far each built-in path moves and turns per frame (metres, degrees). The paths move fast, so
// that 60–120 frames cross much of the scene: at 30 frames a second the ground walk is 42 m/s,
// which tests temporal coherence hard (the oracle's one-frame lag, docs/design.md).
struct FrameStep {
  double metres, degrees;
};
constexpr FrameStep kUnderCanopyStep{0.7, 1.2}, kWalkStep{1.4, 0.8}, kCanopyStep{2.0, 1.5};
constexpr double kHillSpan = 500.0;  // metres, centred on the highest hill's top

// Above the canopy: 40 m over the ground, looking 10° down, kCanopyStep per frame.
std::vector<Camera> canopyPath(const Scene& scene, const terrain::Terrain& terrain, int frames, double aspect) {
  std::vector<Camera> cameras = walkPath(scene, terrain, 1, aspect);
  Camera c = cameras.front();
  cameras.clear();
  const Aabb bounds = terrain.bounds();
  c.pitch = glm::radians(-10.0);
  for (int f = 0; f < frames; ++f) {
    c.position.x = std::clamp(c.position.x, bounds.min.x + 1.0, bounds.max.x - 1.0);
    c.position.z = std::clamp(c.position.z, bounds.min.z + 1.0, bounds.max.z - 1.0);
    c.position.y = terrain.heightAt(c.position.x, c.position.z) + 40.0;
    cameras.push_back(c);
    c.position += kCanopyStep.metres * directionFromYawPitch(c.yaw, 0.0);
    c.yaw += glm::radians(kCanopyStep.degrees);
  }
  return cameras;
}

// Over the highest hill: at eye height from kHillSpan / 2 before its top to as far past it, on the line
// from the scene's start through the top — first facing the hill, then the open view beyond.
std::vector<Camera> hillPath(const Scene& scene, const terrain::Terrain& terrain, int frames, double aspect) {
  const Camera start = walkPath(scene, terrain, 1, aspect).front();
  int highest = 0;
  for (int t = 1; t < terrain.tileCount(); ++t)
    if (terrain.tileBox(t).max.y > terrain.tileBox(highest).max.y) highest = t;
  const glm::dvec3 centre = terrain.tileBox(highest).centre();
  glm::dvec2 top(centre.x, centre.z), direction = top - glm::dvec2(start.position.x, start.position.z);
  direction = glm::length(direction) > 1.0 ? glm::normalize(direction) : glm::dvec2(1.0, 0.0);
  const Aabb bounds = terrain.bounds();
  std::vector<Camera> cameras;
  Camera c = start;
  c.yaw = std::atan2(-direction.x, -direction.y);
  c.pitch = 0.0;
  for (int f = 0; f < frames; ++f) {
    const double s = frames > 1 ? static_cast<double>(f) / (frames - 1) : 0.5;
    const glm::dvec2 p = top + kHillSpan * (s - 0.5) * direction;
    c.position.x = std::clamp(p.x, bounds.min.x + 1.0, bounds.max.x - 1.0);
    c.position.z = std::clamp(p.y, bounds.min.z + 1.0, bounds.max.z - 1.0);
    c.position.y = terrain.heightAt(c.position.x, c.position.z) + 1.7;
    cameras.push_back(c);
  }
  return cameras;
}

constexpr double kStandCell = 20.0;  // metres

std::map<std::pair<int, int>, int> treesPerCell(const vegetation::Forest& forest) {
  std::map<std::pair<int, int>, int> trees;
  for (const vegetation::TreeInstance& t : forest.trees())
    ++trees[{static_cast<int>(std::floor(t.position.x / kStandCell)), static_cast<int>(std::floor(t.position.z / kStandCell))}];
  return trees;
}

// Under the canopy: from the middle of the densest stand at eye height, kUnderCanopyStep per frame
// (along the view, turning) — a slow loop inside it.
std::vector<Camera> underCanopyPath(const Scene& scene, const terrain::Terrain& terrain, const vegetation::Forest& forest, int frames,
                                    double aspect) {
  const glm::dvec2 stand = vegetation::densestStand(forest, kStandCell);
  Camera c = scene.startCamera();
  c.aspect = aspect;
  c.pitch = 0.0;
  c.position = glm::dvec3(stand.x, 0.0, stand.y);
  const double above = scene.camera.above_ground.value_or(1.7);
  const Aabb bounds = terrain.bounds();
  std::vector<Camera> cameras;
  for (int f = 0; f < frames; ++f) {
    c.position.x = std::clamp(c.position.x, bounds.min.x + 1.0, bounds.max.x - 1.0);
    c.position.z = std::clamp(c.position.z, bounds.min.z + 1.0, bounds.max.z - 1.0);
    c.position.y = terrain.heightAt(c.position.x, c.position.z) + above;
    cameras.push_back(c);
    c.position += kUnderCanopyStep.metres * directionFromYawPitch(c.yaw, 0.0);
    c.yaw += glm::radians(kUnderCanopyStep.degrees);
  }
  return cameras;
}

}  // namespace

// A walk from the scene's start, kWalkStep per frame (along the view, turning), eye 1.7 m over the
// ground (or camera.above_ground).
std::vector<Camera> walkPath(const Scene& scene, const terrain::Terrain& terrain, int frames, double aspect) {
  std::vector<Camera> cameras;
  Camera c = scene.startCamera();
  c.aspect = aspect;
  const double above = scene.camera.above_ground.value_or(1.7);
  const Aabb bounds = terrain.bounds();
  for (int f = 0; f < frames; ++f) {
    c.position.x = std::clamp(c.position.x, bounds.min.x + 1.0, bounds.max.x - 1.0);
    c.position.z = std::clamp(c.position.z, bounds.min.z + 1.0, bounds.max.z - 1.0);
    c.position.y = terrain.heightAt(c.position.x, c.position.z) + above;
    cameras.push_back(c);
    const glm::dvec3 forward = directionFromYawPitch(c.yaw, 0.0);
    c.position += kWalkStep.metres * forward;
    c.yaw += glm::radians(kWalkStep.degrees);
  }
  return cameras;
}

glm::dvec2 clearingNear(const vegetation::Forest& forest, const Aabb& bounds, const glm::dvec2& stand) {
  const std::map<std::pair<int, int>, int> trees = treesPerCell(forest);
  const auto treesNear = [&](int cx, int cz) {  // trees in the 3 × 3 cells around (cx, cz): within 30 m of the centre
    int n = 0;
    for (int dz = -1; dz <= 1; ++dz)
      for (int dx = -1; dx <= 1; ++dx)
        if (const auto it = trees.find({cx + dx, cz + dz}); it != trees.end()) n += it->second;
    return n;
  };
  const int sx = static_cast<int>(std::floor(stand.x / kStandCell)), sz = static_cast<int>(std::floor(stand.y / kStandCell));
  for (int ring = 3; ring <= 30; ++ring)  // cells 60–600 m away, nearest rings first
    for (int dz = -ring; dz <= ring; ++dz)
      for (int dx = -ring; dx <= ring; ++dx) {
        if (std::max(std::abs(dx), std::abs(dz)) != ring) continue;
        const glm::dvec2 centre((sx + dx + 0.5) * kStandCell, (sz + dz + 0.5) * kStandCell);
        if (centre.x < bounds.min.x + 30.0 || centre.x > bounds.max.x - 30.0 || centre.y < bounds.min.z + 30.0 || centre.y > bounds.max.z - 30.0)
          continue;  // keep 30 m from the terrain's edge
        if (treesNear(sx + dx, sz + dz) == 0) return centre;
      }
  return stand;
}

std::vector<Camera> filePath(const CameraPath& path, const Scene& scene, const terrain::Terrain& terrain, int frames, double fps,
                             double aspect) {
  std::vector<Camera> cameras;
  for (int f = 0; f < frames; ++f) {
    const CameraPose pose = path.at(path.startTime() + f / fps);
    Camera c = scene.startCamera();
    c.aspect = aspect;
    c.position = pose.position;
    if (path.aboveGround()) c.position.y += terrain.heightAt(pose.position.x, pose.position.z);
    c.yaw = glm::radians(pose.yaw_deg);
    c.pitch = glm::radians(pose.pitch_deg);
    cameras.push_back(c);
  }
  return cameras;
}

std::vector<Camera> benchPath(const std::string& kind, const Scene& scene, const terrain::Terrain& terrain, const vegetation::Forest& forest,
                              int frames, double aspect) {
  if (kind == "forest") return underCanopyPath(scene, terrain, forest, frames, aspect);
  if (kind == "ground") return walkPath(scene, terrain, frames, aspect);
  if (kind == "canopy") return canopyPath(scene, terrain, frames, aspect);
  return hillPath(scene, terrain, frames, aspect);
}

std::string pathDescription(const std::string& kind, int frames) {
  const auto step = [](FrameStep s) { return fmt::format("{} m and {}° a frame", s.metres, s.degrees); };
  if (kind == "forest") return "under the canopy of the densest stand, " + step(kUnderCanopyStep);
  if (kind == "ground") return "ground-level walk through the forest, " + step(kWalkStep);
  if (kind == "canopy") return "open view 40 m above the canopy, " + step(kCanopyStep);
  return fmt::format("crossing the highest hill at eye height, {:.3g} m a frame", kHillSpan / std::max(1, frames - 1));
}

Scene sceneWithTrees(const Scene& full, const CameraPath& path, int trees) {
  Scene scene = full;
  VegetationSettings& v = *scene.vegetation;
  const double size = full.terrain->size, side = size * std::sqrt(static_cast<double>(trees) / full.vegetation->count);
  glm::dvec2 lo(1e300), hi(-1e300);
  for (const PathKey& key : path.keys()) {
    lo = glm::min(lo, glm::dvec2(key.pose.position.x, key.pose.position.z));
    hi = glm::max(hi, glm::dvec2(key.pose.position.x, key.pose.position.z));
  }
  const glm::dvec2 centre = glm::clamp(0.5 * (lo + hi), glm::dvec2(-size / 2 + side / 2), glm::dvec2(size / 2 - side / 2));
  v.count = trees;
  if (side < size) v.area = glm::dvec4(centre - side / 2, centre + side / 2);
  return scene;
}

}  // namespace forest::app
