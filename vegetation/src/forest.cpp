#include "forest/vegetation/forest.hpp"

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <tuple>
#include <numbers>
#include <optional>
#include <unordered_map>

#include "forest/core/error.hpp"
#include "forest/core/log.hpp"
#include "forest/core/random.hpp"
#include "trail.hpp"

namespace forest::vegetation {
namespace {

using glm::dvec2;
using glm::dvec3;

}  // namespace

glm::dvec2 windShear(const VegetationSettings& s, double swayPhase, double time) {
  const double omega = 2.0 * std::numbers::pi / s.wind_period;
  const double sway = (std::sin(omega * time + swayPhase) + 0.3 * std::sin(2.7 * omega * time + 1.7 * swayPhase)) / 1.3;
  return s.wind_strength * sway * s.wind_direction;
}

double windShearChangeBound(const VegetationSettings& s, double dt) {
  // |d/dt (sin(ωt + φ) + 0.3 sin(2.7ωt + 1.7φ))| ≤ ω (1 + 0.3 · 2.7); the sway spans [−1, 1].
  const double omega = 2.0 * std::numbers::pi / s.wind_period;
  const double sway = std::min(2.0, omega * std::abs(dt) * (1.0 + 0.3 * 2.7) / 1.3);
  return std::abs(s.wind_strength) * glm::length(s.wind_direction) * sway;
}

namespace {

}  // namespace

Forest::Forest(const VegetationSettings& settings, const terrain::Terrain& terrain) : settings_(settings), terrain_(terrain) {
  for (Species s : kAllSpecies) {
    const size_t i = static_cast<size_t>(s);
    // A shrub is a fifth of a tree's height: half the LOD0 budget keeps its triangles as dense.
    const int budget = s == Species::Shrub ? std::max(kMinLod0Triangles, settings.lod0_triangles / 2) : settings.lod0_triangles;
    species_[i] = settings.style == TreeStyle::Thesis ? buildThesisTree(s) : buildSpecies(s, budget, settings.seed);
    for (const TreeMesh& lod : species_[i].lods) speciesBounds_[i].extend(lod.bounds);
    // And its query hull, which circumscribes the LODs: a test on the tree's box (the culler's
    // near slab) then holds for what a hull query draws.
    for (const glm::vec3& p : species_[i].queryHull.positions) speciesBounds_[i].extend(dvec3(p));
    querySlabs_[i] = crownSlabs(species_[i], speciesBounds_[i], kQuerySlabs);
    casterSlabs_[i] = fittedCrownSlabs(species_[i], speciesBounds_[i], kCasterSlabs, kCasterSlabCells);
  }
  if (settings.grid > 0) placeOnGrid();
  else place();
  buildClusters();
}

void Forest::buildClusters() {
  clusters_.clear();
  clusterOf_.assign(trees_.size(), 0);
  std::vector<std::uint32_t> all(trees_.size());
  for (std::uint32_t i = 0; i < all.size(); ++i) all[i] = i;
  // Median splits along the longer side until at most kMaxClusterSize trees: halves of more than
  // 32 trees each, so every cluster has 33–64 (unless the forest itself is smaller).
  std::vector<std::vector<std::uint32_t>> stack{std::move(all)};
  while (!stack.empty()) {
    std::vector<std::uint32_t> group = std::move(stack.back());
    stack.pop_back();
    if (group.empty()) continue;
    if (group.size() <= kMaxClusterSize) {
      TreeCluster cluster;
      cluster.trees = std::move(group);
      std::sort(cluster.trees.begin(), cluster.trees.end());
      for (std::uint32_t t : cluster.trees) clusterOf_[t] = static_cast<std::uint32_t>(clusters_.size());
      cluster.bounds = clusterBounds(cluster);
      clusters_.push_back(std::move(cluster));
      continue;
    }
    Aabb box;
    for (std::uint32_t t : group) box.extend(trees_[t].position);
    const int axis = box.extent().x >= box.extent().z ? 0 : 2;
    const auto middle = group.begin() + static_cast<std::ptrdiff_t>(group.size() / 2);
    std::nth_element(group.begin(), middle, group.end(), [&](std::uint32_t a, std::uint32_t b) {
      return trees_[a].position[axis] < trees_[b].position[axis] || (trees_[a].position[axis] == trees_[b].position[axis] && a < b);
    });
    stack.emplace_back(group.begin(), middle);
    stack.emplace_back(middle, group.end());
  }
}

glm::dmat4 Forest::treeTransform(std::uint32_t index, double time) const {
  const TreeInstance& t = trees_[index];
  const dvec2 shear = windShear(settings_, t.swayPhase, time);
  glm::dmat4 m = glm::translate(glm::dmat4(1.0), t.position);
  glm::dmat4 s(1.0);  // x += shear.x · y, z += shear.y · y
  s[1][0] = shear.x;
  s[1][2] = shear.y;
  m = m * s;
  m = glm::rotate(m, t.yaw, dvec3(0.0, 1.0, 0.0));
  return glm::scale(m, dvec3(t.scale));
}

double Forest::tallestTree() const {
  double tallest = 0.0;
  for (const TreeInstance& t : trees_) {
    const Aabb& object = speciesBounds_[static_cast<size_t>(t.species)];
    tallest = std::max(tallest, t.scale * std::max(std::abs(object.max.y), std::abs(object.min.y)));
  }
  return tallest;
}

Aabb Forest::treeBounds(std::uint32_t index) const {
  const TreeInstance& t = trees_[index];
  const Aabb& object = speciesBounds_[static_cast<size_t>(t.species)];
  const glm::dmat4 still = glm::scale(glm::rotate(glm::dmat4(1.0), t.yaw, dvec3(0.0, 1.0, 0.0)), dvec3(t.scale));
  Aabb box;
  for (int c = 0; c < 8; ++c) box.extend(dvec3(still * glm::dvec4(object.corner(c), 1.0)));
  // The shear moves a point at height h by at most strength · |h| horizontally.
  const double reach = settings_.wind_strength * t.scale * std::max(std::abs(object.max.y), std::abs(object.min.y));
  box.min += t.position - dvec3(reach, 0.0, reach);
  box.max += t.position + dvec3(reach, 0.0, reach);
  return box;
}

std::array<Aabb, kQuerySlabs> Forest::treeQueryBoxes(std::uint32_t index) const {
  const TreeInstance& t = trees_[index];
  const Aabb whole = treeBounds(index);
  std::array<Aabb, kQuerySlabs> boxes;
  for (int k = 0; k < kQuerySlabs; ++k) {
    const CrownSlab& slab = querySlabs_[static_cast<size_t>(t.species)][static_cast<size_t>(k)];
    if (slab.empty()) {  // no triangle reaches into this slab: an empty box
      boxes[static_cast<size_t>(k)] = Aabb();
      continue;
    }
    // Uniform scale and a yaw keep the distance from the axis; the shear moves a point at height h
    // by at most strength · |h| (as in treeBounds).
    const double radius = slab.radius * t.scale + settings_.wind_strength * t.scale * std::max(std::abs(slab.bottom), std::abs(slab.top));
    Aabb box{t.position + glm::dvec3(-radius, slab.bottom * t.scale, -radius), t.position + glm::dvec3(radius, slab.top * t.scale, radius)};
    box.min = glm::max(box.min, whole.min);
    box.max = glm::min(box.max, whole.max);
    boxes[static_cast<size_t>(k)] = box;
  }
  return boxes;
}

void Forest::placedCasterSlabs(std::uint32_t index, std::vector<PlacedCrownSlab>& out) const {
  const TreeInstance& t = trees_[index];
  for (const CrownSlab& slab : casterSlabs_[static_cast<size_t>(t.species)]) {
    if (slab.empty()) continue;
    const double sway = settings_.wind_strength * t.scale * std::max(std::abs(slab.bottom), std::abs(slab.top));
    out.push_back({t.position, t.position.y + slab.bottom * t.scale, t.position.y + slab.top * t.scale,
                   slab.radiusBottom * t.scale + sway, slab.radiusTop * t.scale + sway});
  }
}

int Forest::lodFor(std::uint32_t tree, const glm::dvec3& eye) const {
  if (settings_.force_lod0) return 0;
  // Bands scaled by the size class (a tree twice as tall keeps its detail twice as far); a young
  // tree's chain starts at LOD1.
  const TreeInstance& t = trees_[tree];
  const double distance = lodDistance(tree, eye);
  const glm::dvec3& d = settings_.lod_distances;
  const int lod = distance < d.x ? 0 : distance < d.y ? 1 : distance < d.z ? 2 : 3;
  return t.size == SizeClass::Young ? std::max(lod, 1) : lod;
}

double Forest::lodDistance(std::uint32_t tree, const glm::dvec3& eye) const {
  const TreeInstance& t = trees_[tree];
  return glm::distance(eye, t.position) / settings_.sizes.scale[static_cast<int>(t.size)];
}

Aabb Forest::clusterBounds(const TreeCluster& cluster) const {
  Aabb box;
  for (std::uint32_t t : cluster.trees) box.extend(treeBounds(t));
  return box;
}

std::vector<std::uint32_t> Forest::moveTrees(std::span<const Move> moves) {
  std::vector<std::uint32_t> changed;
  for (const Move& move : moves) {
    if (move.tree >= trees_.size()) throw Error("Forest::moveTrees: no tree " + std::to_string(move.tree));
    TreeInstance& t = trees_[move.tree];
    t.position = {move.xz.x, terrain_.heightAt(move.xz.x, move.xz.y), move.xz.y};
    t.yaw = move.yaw;
    changed.push_back(clusterOf_[move.tree]);
  }
  std::sort(changed.begin(), changed.end());
  changed.erase(std::unique(changed.begin(), changed.end()), changed.end());
  for (std::uint32_t c : changed) clusters_[c].bounds = clusterBounds(clusters_[c]);
  return changed;
}

glm::dvec2 densestStand(const Forest& forest, double cell) {
  std::map<std::pair<std::int64_t, std::int64_t>, int> trees;
  for (const TreeInstance& t : forest.trees())
    ++trees[{static_cast<std::int64_t>(std::floor(t.position.x / cell)), static_cast<std::int64_t>(std::floor(t.position.z / cell))}];
  std::pair<std::int64_t, std::int64_t> densest{0, 0};
  int most = -1;
  for (const auto& [square, count] : trees)
    if (count > most) std::tie(densest, most) = std::tie(square, count);
  return {(static_cast<double>(densest.first) + 0.5) * cell, (static_cast<double>(densest.second) + 0.5) * cell};
}

std::pair<glm::dvec2, glm::dvec2> Forest::placementArea() const {
  const terrain::Heightfield& h = terrain_.heightfield();
  constexpr double inset = 1.0;
  dvec2 lo(h.origin().x + inset, h.origin().y + inset), hi(h.origin().x + h.size() - inset, h.origin().y + h.size() - inset);
  if (settings_.area) {
    lo = glm::max(lo, dvec2(settings_.area->x, settings_.area->y));
    hi = glm::max(lo, glm::min(hi, dvec2(settings_.area->z, settings_.area->w)));  // off the terrain: empty
  }
  return {lo, hi};
}

double Forest::areaHa() const {
  // Trees stand within 1 m of the terrain's edge (the placement's inset); the area is the terrain's.
  const terrain::Heightfield& h = terrain_.heightfield();
  if (!settings_.area) return h.size() * h.size() / 1e4;
  const dvec2 lo = glm::max(h.origin(), dvec2(settings_.area->x, settings_.area->y));
  const dvec2 hi = glm::min(h.origin() + dvec2(h.size()), dvec2(settings_.area->z, settings_.area->w));
  return std::max(hi.x - lo.x, 0.0) * std::max(hi.y - lo.y, 0.0) / 1e4;
}

ForestStats forestStats(const Forest& forest) {
  ForestStats stats;
  stats.trees = static_cast<int>(forest.trees().size());
  stats.requested = forest.requestedCount();
  stats.terrainAreaHa = forest.areaHa();
  for (const TreeInstance& tree : forest.trees()) {
    ++stats.perSpecies[static_cast<size_t>(tree.species)];
    ++stats.perSpeciesAndSize[static_cast<size_t>(tree.species)][static_cast<size_t>(tree.size)];
    if (forest.stands() && forest.stands()->inStand(tree.position.x, tree.position.z)) ++stats.inStands;
  }
  if (forest.stands()) {
    stats.standAreaHa = forest.stands()->standShare() * stats.terrainAreaHa;
    if (stats.standAreaHa > 0.0) stats.stemsPerHaInStands = stats.inStands / stats.standAreaHa;
  }
  if (stats.trees > 0) stats.shareInStands = static_cast<double>(stats.inStands) / stats.trees;
  return stats;
}

}  // namespace forest::vegetation
