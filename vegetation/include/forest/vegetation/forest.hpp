#pragma once
// The trees of a scene (DESIGN §4 vegetation/): Poisson-disk (or jittered-grid) placement on the terrain, per-tree
// variation, spatial clusters of 16–64 trees (the culling hierarchy's leaves), the LOD as a pure
// function of the camera, wind sway as a pure function of (tree, time), and moves between frames.
#include <glm/glm.hpp>

#include <array>
#include <optional>
#include <cstdint>
#include <span>
#include <vector>

#include "forest/core/bounds.hpp"
#include "forest/core/scene.hpp"
#include "forest/terrain/terrain.hpp"
#include "forest/vegetation/crown_slabs.hpp"
#include "forest/vegetation/species.hpp"
#include "forest/vegetation/stand_field.hpp"

namespace forest::vegetation {

struct TreeInstance {
  Species species = Species::Conifer;
  SizeClass size = SizeClass::Mature;  // scale and LOD chain ([vegetation.sizes])
  glm::dvec3 position{0.0};   // base, on the terrain
  double yaw = 0.0;           // radians about +y
  double scale = 1.0;         // the class's scale × the per-tree variation
  glm::vec3 tint{1.0f};       // albedo multiplier
  double swayPhase = 0.0;     // radians
};

struct TreeCluster {
  std::vector<std::uint32_t> trees;  // indices into Forest::trees()
  Aabb bounds;                       // union of the trees' boxes, sway included
};

constexpr int kMinClusterSize = 16;
constexpr int kMaxClusterSize = 64;

// Wind sway (a shear about the tree's base: x += s.x · h, z += s.y · h at height h above it):
// s = strength · direction · (sin(ωt + φ) + 0.3 sin(2.7ωt + 1.7φ)) / 1.3, ω = 2π / period, so
// |s| ≤ strength. The same formula runs in trees.vert; being affine, it keeps instancing exact
// for ray tracing too.
glm::dvec2 windShear(const VegetationSettings& settings, double swayPhase, double time);
// How far the shear can change in `dt` seconds, for any tree and any start time:
// |s(t + dt) − s(t)| ≤ strength · |direction| · min(2, ω |dt| (1 + 0.3 · 2.7) / 1.3) — the sway's
// range, and its largest slope times dt. A point h above its tree's base moves at most h times this.
double windShearChangeBound(const VegetationSettings& settings, double dt);

class Forest {
 public:
  // Builds the species meshes and places the trees (log reports when fewer fit than requested).
  Forest(const VegetationSettings& settings, const terrain::Terrain& terrain);

  const VegetationSettings& settings() const { return settings_; }
  const std::array<SpeciesModel, kSpeciesCount>& species() const { return species_; }
  const SpeciesModel& model(Species s) const { return species_[static_cast<size_t>(s)]; }
  const std::vector<TreeInstance>& trees() const { return trees_; }
  const std::vector<TreeCluster>& clusters() const { return clusters_; }
  int requestedCount() const { return settings_.grid > 0 ? settings_.grid * settings_.grid : settings_.count; }
  // The density field the trees were placed by ([vegetation.stands]); null when spread evenly.
  const StandField* stands() const { return stands_ ? &*stands_ : nullptr; }
  // Where trees are placed: (x0, z0) and (x1, z1) of the terrain 1 m in from its edges, cut to
  // [vegetation] area where given.
  std::pair<glm::dvec2, glm::dvec2> placementArea() const;
  // Its area in hectares as the stats count it: the whole terrain's without [vegetation] area.
  double areaHa() const;

  // Object → world at `time`: translate · windShear · rotateY(yaw) · scale.
  glm::dmat4 treeTransform(std::uint32_t tree, double time) const;
  // The height of the tallest tree's top above its base (metres; 0 without trees): the longest
  // lever the wind's shear has.
  double tallestTree() const;
  // World box of a tree over all times (sway inflated by the largest shear) and all LODs.
  Aabb treeBounds(std::uint32_t tree) const;
  // Tighter: kQuerySlabs boxes whose union holds the tree at all times and LODs — one per height
  // slab, as wide as the species' widest point in that slab (its radius from the trunk's axis, so
  // any yaw), grown by the sway at the slab's top, each cut to treeBounds. The culler queries with
  // them (a crown's box no longer shows where only its corners would).
  std::array<Aabb, kQuerySlabs> treeQueryBoxes(std::uint32_t tree) const;
  // The tree's caster slabs (casterSlabs) in the world, holding it at all times: each non-empty
  // one's frustum scaled and over its base, the radii grown by the wind's largest shift at the
  // slab's ends (as treeQueryBoxes). Appended to `out`.
  void placedCasterSlabs(std::uint32_t tree, std::vector<PlacedCrownSlab>& out) const;
  // The species' height slabs in object space over all LODs (crown_slabs.hpp): kQuerySlabs equal
  // ones (the query boxes'), and kCasterSlabs fitted to its shape (the GPU caster filter's).
  const std::vector<CrownSlab>& querySlabs(Species species) const { return querySlabs_[static_cast<size_t>(species)]; }
  const std::vector<CrownSlab>& casterSlabs(Species species) const { return casterSlabs_[static_cast<size_t>(species)]; }
  // LOD by distance bands from the eye to the tree's base, divided by its size class's scale; a
  // young tree never takes LOD0 (force_lod0 → 0 for all): a pure function of the camera, so
  // culling never changes what is drawn.
  int lodFor(std::uint32_t tree, const glm::dvec3& eye) const;
  // The distance lodFor compares with its bands: from `eye` to the tree's base over its size class's scale.
  double lodDistance(std::uint32_t tree, const glm::dvec3& eye) const;

  // Moves trees between frames (base snapped to the terrain); returns the clusters whose boxes
  // changed, in increasing order.
  struct Move {
    std::uint32_t tree;
    glm::dvec2 xz;
    double yaw;
  };
  std::vector<std::uint32_t> moveTrees(std::span<const Move> moves);

 private:
  void place();        // Poisson-disk dart throwing (count, spacing, slope, height band)
  void placeOnGrid();  // jittered regular grid (settings.grid > 0)
  TreeInstance varied(Species species, SizeClass size, const glm::dvec3& base, const double (&variation)[5]) const;
  void buildClusters();
  Aabb clusterBounds(const TreeCluster& cluster) const;

  VegetationSettings settings_;
  const terrain::Terrain& terrain_;
  std::array<SpeciesModel, kSpeciesCount> species_;
  std::array<Aabb, kSpeciesCount> speciesBounds_;  // object space, all LODs
  std::array<std::vector<CrownSlab>, kSpeciesCount> querySlabs_, casterSlabs_;
  std::vector<TreeInstance> trees_;
  std::vector<TreeCluster> clusters_;
  std::vector<std::uint32_t> clusterOf_;
  std::optional<StandField> stands_;
};

// What `forest check --stats` prints: the placed trees per species, and how many stand in stands
// (the density field's g ≥ τ) on how much area.
struct ForestStats {
  int trees = 0, requested = 0;
  std::array<int, kSpeciesCount> perSpecies{};
  std::array<std::array<int, kSizeClassCount>, kSpeciesCount> perSpeciesAndSize{};
  double terrainAreaHa = 0.0;
  double standAreaHa = 0.0;          // cover measured on the field's sample grid × terrain area; 0 without stands
  int inStands = 0;
  double shareInStands = 0.0;        // inStands / trees
  double stemsPerHaInStands = 0.0;   // inStands / standAreaHa; 0 without stands
};
ForestStats forestStats(const Forest& forest);

// The middle of the densest stand: the centre (x, z) of the `cell` × `cell` square of the world
// grid holding the most trees (the first in (x, z) order among equals). Benchmarks and tests stand
// under the canopy there.
glm::dvec2 densestStand(const Forest& forest, double cell = 20.0);

}  // namespace forest::vegetation
