// Crown slabs (vegetation/crown_slabs.hpp): the frustum of each height slab holds every point of
// every triangle of every LOD inside the slab, and on a cone it is the cone.
#include <gtest/gtest.h>

#include <cmath>
#include <algorithm>
#include <cstdio>
#include <string>
#include <numbers>
#include <optional>
#include <random>

#include "forest/vegetation/crown_slabs.hpp"
#include "forest/vegetation/species.hpp"
#include "forest/core/bounds.hpp"

namespace forest::vegetation {
namespace {

using glm::dvec3;

// A cone of radius `radius` at y = 0 with its apex at y = height, `sides` triangles round it
// (every LOD the same): its slabs' frusta are the cone's own radii at their heights.
SpeciesModel coneModel(double radius, double height, int sides) {
  TreeMesh mesh;
  mesh.positions.emplace_back(0.0f, static_cast<float>(height), 0.0f);
  for (int i = 0; i < sides; ++i) {
    const double angle = 2.0 * std::numbers::pi * i / sides;
    mesh.positions.emplace_back(static_cast<float>(radius * std::cos(angle)), 0.0f, static_cast<float>(radius * std::sin(angle)));
  }
  for (int i = 0; i < sides; ++i) {
    mesh.indices.insert(mesh.indices.end(), {0u, static_cast<std::uint32_t>(1 + (i + 1) % sides), static_cast<std::uint32_t>(1 + i)});
  }
  for (const glm::vec3& p : mesh.positions) mesh.bounds.extend(dvec3(p));
  SpeciesModel model;
  model.lods.fill(mesh);
  return model;
}

TEST(CrownSlabs, OfAConeAreTheConesRadii) {
  const double radius = 3.0, height = 8.0;
  const SpeciesModel cone = coneModel(radius, height, 64);
  const std::vector<CrownSlab> slabs = crownSlabs(cone, cone.lods[0].bounds, kQuerySlabs);
  ASSERT_EQ(slabs.size(), static_cast<size_t>(kQuerySlabs));
  for (int k = 0; k < kQuerySlabs; ++k) {
    const CrownSlab& s = slabs[static_cast<size_t>(k)];
    const double y0 = height * k / kQuerySlabs, y1 = height * (k + 1) / kQuerySlabs;
    ASSERT_FALSE(s.empty()) << k;
    EXPECT_NEAR(s.bottom, y0, 1e-5) << k;
    EXPECT_NEAR(s.top, y1, 1e-5) << k;
    // The cone's radius at a height (the vertices lie on its circle: the polygon's corners reach it).
    EXPECT_NEAR(s.radiusBottom, radius * (1.0 - y0 / height), 1e-5) << k;
    EXPECT_NEAR(s.radiusTop, radius * (1.0 - y1 / height), 1e-5) << k;
    EXPECT_NEAR(s.radius, s.radiusBottom, 1e-5) << k;  // the widest: at the slab's floor
  }
}

// Two cones stacked, the upper one's skirt 2 m above the lower one's floor: fitted slabs cut at the
// skirt (a cut there follows both tapers; anywhere else a slab holds a skirt above its floor).
TEST(CrownSlabs, FittedOnesCutAtATiersSkirt) {
  SpeciesModel lower = coneModel(3.0, 4.0, 64), upper = coneModel(2.0, 4.0, 64);
  TreeMesh both = lower.lods[0];
  for (const glm::vec3& p : upper.lods[0].positions) both.positions.push_back(p + glm::vec3(0.0f, 2.0f, 0.0f));
  for (std::uint32_t i : upper.lods[0].indices) both.indices.push_back(i + static_cast<std::uint32_t>(lower.lods[0].positions.size()));
  for (const glm::vec3& p : both.positions) both.bounds.extend(dvec3(p));
  SpeciesModel model;
  model.lods.fill(both);
  const std::vector<CrownSlab> slabs = fittedCrownSlabs(model, both.bounds, 2, 12);  // cells of 0.5 m
  ASSERT_EQ(slabs.size(), 2u);
  EXPECT_NEAR(slabs[0].bottom, 0.0, 1e-6);
  EXPECT_NEAR(slabs[0].top, 2.0, 1e-6);
  EXPECT_NEAR(slabs[1].bottom, 2.0, 1e-6);
  EXPECT_NEAR(slabs[1].top, 6.0, 1e-6);
  // Below the skirt the lower cone (3 → 1.5 m); above it the upper one's skirt and apex (2 → 0 m),
  // which the lower cone's part there (1.5 → 0.0 at 4 m) stays inside.
  EXPECT_NEAR(slabs[0].radiusBottom, 3.0, 1e-5);
  EXPECT_NEAR(slabs[0].radiusTop, 1.5, 1e-5);
  EXPECT_NEAR(slabs[1].radiusBottom, 2.0, 1e-5);
  EXPECT_NEAR(slabs[1].radiusTop, 0.0, 1e-5);
}

// Whether every point of every triangle of every LOD (corners, edge points and inner points on a
// lattice) lies inside a slab whose height range holds it: within its frustum's radius there.
void expectHoldsEveryPoint(const SpeciesModel& model, const std::vector<CrownSlab>& slabs, const std::string& what) {
  for (const TreeMesh& mesh : model.lods) {
    for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
      const dvec3 a(mesh.positions[mesh.indices[t]]), b(mesh.positions[mesh.indices[t + 1]]), c(mesh.positions[mesh.indices[t + 2]]);
      constexpr int kSteps = 6;
      for (int i = 0; i <= kSteps; ++i)
        for (int j = 0; j <= kSteps - i; ++j) {
          const dvec3 p = a + (b - a) * (static_cast<double>(i) / kSteps) + (c - a) * (static_cast<double>(j) / kSteps);
          const bool held = std::any_of(slabs.begin(), slabs.end(), [&](const CrownSlab& s) {
            return !s.empty() && p.y >= s.bottom - 1e-6 && p.y <= s.top + 1e-6 && std::hypot(p.x, p.z) <= s.radiusAt(p.y) + 1e-6;
          });
          ASSERT_TRUE(held) << what << " triangle " << t / 3 << " point (" << p.x << ", " << p.y << ", " << p.z << ") radius "
                            << std::hypot(p.x, p.z);
        }
    }
  }
}

// The outline seen from the side, Σ ∫ 2 r(y) dy: the frusta's, and the cylinders'.
double frustaOutline(const std::vector<CrownSlab>& slabs) {
  double area = 0.0;
  for (const CrownSlab& s : slabs) area += s.empty() ? 0.0 : (s.radiusBottom + s.radiusTop) * (s.top - s.bottom);
  return area;
}
double cylindersOutline(const std::vector<CrownSlab>& slabs) {
  double area = 0.0;
  for (const CrownSlab& s : slabs) area += s.empty() ? 0.0 : 2.0 * s.radius * (s.top - s.bottom);
  return area;
}

// Each species' query slabs and caster slabs hold every point; the frusta are no wider than their
// cylinders; the fitted caster slabs wrap the conifer's tiers in under 0.8 of the outline of the
// four equal cylinders (a tier's taper is half its skirt's radius over its height).
TEST(CrownSlabs, HoldEveryPointOfEverySpecies) {
  for (Species species : kAllSpecies) {
    const SpeciesModel model = buildSpecies(species, 2000, 7);
    Aabb bounds;
    for (const TreeMesh& lod : model.lods) bounds.extend(lod.bounds);
    const std::vector<CrownSlab> query = crownSlabs(model, bounds, kQuerySlabs);
    const std::vector<CrownSlab> caster = fittedCrownSlabs(model, bounds, kCasterSlabs, kCasterSlabCells);
    const std::string name(speciesName(species));
    for (const std::vector<CrownSlab>* slabs : {&query, &caster})
      for (const CrownSlab& s : *slabs) {
        if (s.empty()) continue;
        EXPECT_LE(std::max(s.radiusBottom, s.radiusTop), s.radius);
        EXPECT_GE(std::min(s.radiusBottom, s.radiusTop), 0.0);
      }
    for (const CrownSlab& s : caster)
      if (!s.empty())
        std::printf("[crown slabs] %s [%.2f, %.2f] m: radius %.2f, frustum %.2f -> %.2f\n", name.c_str(), s.bottom, s.top, s.radius,
                    s.radiusBottom, s.radiusTop);
    std::printf("[crown slabs] %s: outline of the fitted frusta %.2f of the equal cylinders'\n", name.c_str(),
                frustaOutline(caster) / cylindersOutline(query));
    expectHoldsEveryPoint(model, query, name + " (query slabs)");
    expectHoldsEveryPoint(model, caster, name + " (caster slabs)");
    if (species == Species::Conifer) {
      EXPECT_LT(frustaOutline(caster), 0.8 * cylindersOutline(query));
    }
  }
}

// grownBounds holds every point lineSpan counts inside: random lines through random slabs (steep,
// flat, widening, narrowing, thin), the points at both ends of the span and between, against the
// box — whose sides must also be reached (the bound is not loose by more than the slope's share).
TEST(CrownSlabs, GrownBoundsHoldEveryPointALineSpanTakes) {
  std::mt19937 random(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int spans = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    PlacedCrownSlab slab;
    slab.base = dvec3(10.0 * unit(random) - 5.0, 3.0 * unit(random), 10.0 * unit(random) - 5.0);
    slab.bottom = slab.base.y + 8.0 * unit(random);
    slab.top = slab.bottom + (trial % 5 == 0 ? 0.05 : 6.0) * unit(random);
    slab.radiusBottom = 3.0 * unit(random);
    slab.radiusTop = 3.0 * unit(random);
    const double grow = trial % 3 == 0 ? 0.0 : 0.5 * unit(random);
    const Aabb box = slab.grownBounds(grow);
    for (int line = 0; line < 20; ++line) {
      const dvec3 a = slab.base + dvec3(20.0 * unit(random) - 10.0, 20.0 * unit(random) - 5.0, 20.0 * unit(random) - 10.0);
      const dvec3 d = dvec3(2.0 * unit(random) - 1.0, 2.0 * unit(random) - 1.0, 2.0 * unit(random) - 1.0);
      const std::optional<glm::dvec2> span = slab.lineSpan(a, d, grow);
      if (!span) continue;
      ++spans;
      for (const double t : {0.0, 0.25, 0.5, 0.75, 1.0}) {
        const dvec3 p = a + (span->x + t * (span->y - span->x)) * d;
        ASSERT_TRUE(box.contains(p, 1e-9)) << "trial " << trial << " point " << p.x << " " << p.y << " " << p.z;
      }
    }
  }
  EXPECT_GT(spans, 1000);
}

}  // namespace
}  // namespace forest::vegetation
