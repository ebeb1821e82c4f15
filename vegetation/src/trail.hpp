#pragma once
// A walkway kept free of trees ([vegetation.trail], core/scene.hpp TrailSettings): whether a tree
// would reach into it — some triangle of its LOD0 mesh within the walkway's height band (0.3 to 3 m
// above the ground at the trail's nearest point, where a walker's eye and near plane are) coming
// nearer than width / 2 to the trail's polyline, with the largest wind sway added (internal to
// vegetation/).
#include <array>
#include <vector>

#include "forest/core/scene.hpp"
#include "forest/terrain/terrain.hpp"
#include "forest/vegetation/forest.hpp"
#include "forest/vegetation/species.hpp"

namespace forest::vegetation {

class TrailClearance {
 public:
  TrailClearance(const TrailSettings& trail, const std::array<SpeciesModel, kSpeciesCount>& species, double windStrength,
                 const terrain::Terrain& terrain);
  // Whether the tree, placed as given (base, yaw, scale), reaches into the walkway.
  bool reaches(const TreeInstance& tree) const;

  static constexpr double kBandLow = 0.3, kBandHigh = 3.0;  // metres above the trail's ground

 private:
  // Per triangle of a species' LOD0: its height range and its farthest horizontal reach from the
  // trunk's axis, in object space (the reach is the same for any yaw).
  struct TriangleReach {
    float low, high, radius;
  };
  // The trail's point nearest to p.
  glm::dvec2 nearestOnTrail(const glm::dvec2& p) const;

  TrailSettings trail_;
  const terrain::Terrain& terrain_;
  double windStrength_;
  std::array<std::vector<TriangleReach>, kSpeciesCount> reach_;
  std::array<double, kSpeciesCount> widest_{};  // the largest radius of each species (a quick reject)
  glm::dvec2 trailMin_{1e300}, trailMax_{-1e300};  // the trail's bounding rectangle (x, z)
  double groundTop_ = 0.0;                        // the terrain's highest point
};

}  // namespace forest::vegetation
