#include "trail.hpp"

#include <algorithm>
#include <cmath>

namespace forest::vegetation {

TrailClearance::TrailClearance(const TrailSettings& trail, const std::array<SpeciesModel, kSpeciesCount>& species, double windStrength,
                               const terrain::Terrain& terrain)
    : trail_(trail), terrain_(terrain), windStrength_(windStrength) {
  for (std::size_t s = 0; s < species.size(); ++s) {
    const TreeMesh& mesh = species[s].lods[0];
    for (std::size_t k = 0; k + 2 < mesh.indices.size(); k += 3) {
      TriangleReach t{1e30f, -1e30f, 0.0f};
      for (std::size_t c = 0; c < 3; ++c) {
        const glm::vec3 v = mesh.positions[mesh.indices[k + c]];
        t.low = std::min(t.low, v.y);
        t.high = std::max(t.high, v.y);
        t.radius = std::max(t.radius, std::hypot(v.x, v.z));
      }
      reach_[s].push_back(t);
      widest_[s] = std::max(widest_[s], double(t.radius));
    }
  }
  for (const glm::dvec2& p : trail_.points) {
    trailMin_ = glm::min(trailMin_, p);
    trailMax_ = glm::max(trailMax_, p);
  }
  groundTop_ = terrain.bounds().max.y;
}

glm::dvec2 TrailClearance::nearestOnTrail(const glm::dvec2& p) const {
  glm::dvec2 nearest = trail_.points.front();
  for (std::size_t i = 0; i + 1 < trail_.points.size(); ++i) {
    const glm::dvec2 a = trail_.points[i], ab = trail_.points[i + 1] - a;
    const double length2 = glm::dot(ab, ab);
    const double s = length2 > 0.0 ? std::clamp(glm::dot(p - a, ab) / length2, 0.0, 1.0) : 0.0;
    if (glm::distance(p, a + s * ab) < glm::distance(p, nearest)) nearest = a + s * ab;
  }
  return nearest;
}

bool TrailClearance::reaches(const TreeInstance& tree) const {
  const std::size_t s = static_cast<std::size_t>(tree.species);
  const double halfWidth = 0.5 * trail_.width;
  const glm::dvec2 base(tree.position.x, tree.position.z);
  // Far from the trail's bounding rectangle (a landscape's trees but a few): no test per segment.
  // The sway below is at most that of the band's top over the terrain's highest point.
  const double swayBound = windStrength_ * std::max(0.0, groundTop_ - tree.position.y + kBandHigh);
  const glm::dvec2 outside = glm::max(glm::max(trailMin_ - base, base - trailMax_), glm::dvec2(0.0));
  if (glm::length(outside) >= widest_[s] * tree.scale + swayBound + halfWidth) return false;
  const glm::dvec2 onTrail = nearestOnTrail(base);
  const double distance = glm::distance(base, onTrail);
  // The band in the tree's object space (its base at 0), and the widest triangle within it; the
  // sway shifts a point at height h by up to strength · h.
  const double ground = terrain_.heightAt(onTrail.x, onTrail.y) - tree.position.y;
  const double sway = windStrength_ * std::max(0.0, ground + kBandHigh);
  if (distance >= widest_[s] * tree.scale + sway + halfWidth) return false;
  const double low = (ground + kBandLow) / tree.scale, high = (ground + kBandHigh) / tree.scale;
  double radius = 0.0;
  for (const TriangleReach& t : reach_[s])
    if (t.high >= low && t.low <= high) radius = std::max(radius, double(t.radius));
  return distance < radius * tree.scale + sway + halfWidth;
}

}  // namespace forest::vegetation
