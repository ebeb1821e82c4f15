// The forest: Poisson-disk placement on the terrain (count, spacing, slope, height band, bases on
// the ground), determinism, clusters of 16–64 trees with their boxes, sway inside the inflated
// boxes at any time, moves reporting the changed clusters, LOD by distance bands; the thesis demo
// preset (jittered grid of closed cone-and-ring trees).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <set>
#include <tuple>

#include "forest/core/camera_path.hpp"
#include "forest/core/scene.hpp"
#include "forest/vegetation/forest.hpp"
#include "test_paths.hpp"

namespace forest::vegetation {
namespace {

using glm::dvec3;

const terrain::Terrain& testTerrain() {
  static const terrain::Terrain terrain([] {
    TerrainSettings s;
    s.size = 500.0;
    s.samples = 257;
    s.height_min = 0.0;
    s.height_max = 60.0;
    s.feature_size = 400.0;
    s.octaves = 6;
    s.seed = 3;
    return s;
  }());
  return terrain;
}

VegetationSettings testVegetation(int count, std::uint64_t seed = 1) {
  VegetationSettings v;
  v.count = count;
  v.seed = seed;
  v.lod0_triangles = 1000;
  v.conifer = {0.6, 4.0, 30.0, -1e4, 1e4};
  v.broadleaf = {0.4, 6.0, 20.0, 10.0, 45.0};  // a height band
  return v;
}

const Forest& sharedForest() {
  static const Forest forest(testVegetation(2000), testTerrain());
  return forest;
}

TEST(TreePlacement, HonoursCountSpacingSlopeHeightAndGround) {
  const Forest& f = sharedForest();
  const terrain::Terrain& t = testTerrain();
  ASSERT_EQ(f.trees().size(), 2000u);
  int conifers = 0;
  for (size_t i = 0; i < f.trees().size(); ++i) {
    const TreeInstance& a = f.trees()[i];
    const SpeciesPlacementSettings& rule = a.species == Species::Conifer ? f.settings().conifer : f.settings().broadleaf;
    conifers += a.species == Species::Conifer ? 1 : 0;
    EXPECT_NEAR(a.position.y, t.heightAt(a.position.x, a.position.z), 0.01) << i;  // base on the ground
    const double slope = glm::degrees(std::acos(t.normalAt(a.position.x, a.position.z).y));
    EXPECT_LE(slope, rule.max_slope_deg + 1e-9) << i;
    EXPECT_GE(a.position.y, rule.min_height) << i;
    EXPECT_LE(a.position.y, rule.max_height) << i;
    for (size_t j = i + 1; j < f.trees().size(); ++j) {
      const TreeInstance& b = f.trees()[j];
      const double spacing = std::max(rule.spacing, (b.species == Species::Conifer ? f.settings().conifer : f.settings().broadleaf).spacing);
      ASSERT_GE(glm::distance(glm::dvec2(a.position.x, a.position.z), glm::dvec2(b.position.x, b.position.z)), spacing)
          << i << ", " << j;
    }
  }
  EXPECT_GT(conifers, 1000);  // broadleaves are limited to a height band and gentler slopes
  EXPECT_LT(conifers, 2000);
}

// [vegetation] area: every tree inside the rectangle's part on the terrain (±250 m; 1 m inset), and
// the stats count that part's hectares.
TEST(TreePlacement, StaysInsideItsArea) {
  VegetationSettings inside = testVegetation(150);
  inside.area = glm::dvec4(-100.0, -50.0, 50.0, 100.0);
  VegetationSettings overEdge = testVegetation(40);
  overEdge.area = glm::dvec4(200.0, 180.0, 400.0, 400.0);
  for (const auto& [settings, lo, hi, hectares] : {std::tuple{inside, glm::dvec2(-100.0, -50.0), glm::dvec2(50.0, 100.0), 2.25},
                                                   std::tuple{overEdge, glm::dvec2(200.0, 180.0), glm::dvec2(249.0, 249.0), 50.0 * 70.0 / 1e4}}) {
    const Forest forest(settings, testTerrain());
    ASSERT_EQ(forest.trees().size(), static_cast<size_t>(settings.count));
    for (const TreeInstance& t : forest.trees()) {
      EXPECT_GE(t.position.x, lo.x);
      EXPECT_LE(t.position.x, hi.x);
      EXPECT_GE(t.position.z, lo.y);
      EXPECT_LE(t.position.z, hi.y);
    }
    EXPECT_NEAR(forestStats(forest).terrainAreaHa, hectares, 1e-9);
  }
}

TEST(TreePlacement, SharesWithoutLimits) {
  VegetationSettings v = testVegetation(1000);
  v.conifer = {0.6, 4.0, 90.0, -1e4, 1e4};
  v.broadleaf = {0.4, 4.0, 90.0, -1e4, 1e4};
  const Forest f(v, testTerrain());
  ASSERT_EQ(f.trees().size(), 1000u);
  const auto conifers = std::count_if(f.trees().begin(), f.trees().end(), [](const TreeInstance& t) { return t.species == Species::Conifer; });
  EXPECT_NEAR(static_cast<double>(conifers) / 1000.0, 0.6, 0.05);
}

// [vegetation.stands]: a dart is kept with probability D (the density field), so, where spacing
// never refuses one (1500 trees at 0.5 m on 25 ha), the share of trees in stands is the field's
// own: p = ∫_stands D / ∫ D over the terrain (a 500² midpoint sum here, not the placement), within
// 4 binomial standard deviations. Ignoring the field (p = cover) or inverting it fails.
TEST(TreePlacement, StandsFollowTheDensityField) {
  VegetationSettings v = testVegetation(1500, 5);
  v.conifer = {0.6, 0.5, 90.0, -1e4, 1e4};
  v.broadleaf = {0.4, 0.5, 90.0, -1e4, 1e4};
  v.stands = StandSettings{0.2, 80.0, 0.3, 0.1};
  const Forest f(v, testTerrain());
  ASSERT_EQ(f.trees().size(), 1500u);
  ASSERT_NE(f.stands(), nullptr);
  const StandField& field = *f.stands();
  const terrain::Heightfield& h = testTerrain().heightfield();
  double all = 0.0, inStands = 0.0, standCells = 0.0;
  constexpr int kCells = 500;
  for (int j = 0; j < kCells; ++j)
    for (int i = 0; i < kCells; ++i) {
      const double x = h.origin().x + 1.0 + (i + 0.5) * (h.size() - 2.0) / kCells;
      const double z = h.origin().y + 1.0 + (j + 0.5) * (h.size() - 2.0) / kCells;
      const double d = field.density(x, z);
      EXPECT_GE(d, 0.1);
      EXPECT_LE(d, 1.0);
      all += d;
      if (field.inStand(x, z)) {
        inStands += d;
        standCells += 1.0;
      }
    }
  // The stands cover what was asked, on this finer grid too (the quantile's grid is 256²).
  EXPECT_NEAR(standCells / (kCells * kCells), 0.2, 0.01);
  const double p = inStands / all;
  const double placed = static_cast<double>(std::count_if(f.trees().begin(), f.trees().end(), [&](const TreeInstance& t) {
                          return field.inStand(t.position.x, t.position.z);
                        })) / 1500.0;
  EXPECT_NEAR(placed, p, 4.0 * std::sqrt(p * (1.0 - p) / 1500.0)) << "expected share " << p;
  EXPECT_GT(p, 0.5);  // the case means something: most trees stand on a fifth of the land
  const ForestStats stats = forestStats(f);
  EXPECT_EQ(stats.inStands, static_cast<int>(std::lround(placed * 1500.0)));
  EXPECT_NEAR(stats.standAreaHa, field.standShare() * 25.0, 1e-9);
  EXPECT_NEAR(stats.stemsPerHaInStands, stats.inStands / stats.standAreaHa, 1e-9);
}

// Species by site: with equal shares, conifer altitude_bias +1 and broadleaf −1, the weights at
// altitude a are 2a and 2(1 − a), so a tree at a is a conifer with probability a (scene.hpp). Per
// fifth of the altitude range the conifers' share is the mean a of its trees, within 4 binomial
// standard deviations (and 0.02 for the bins' width). Biases ignored (p = 1/2 everywhere) or
// reversed fail in the top and bottom fifths.
TEST(TreePlacement, SpeciesFollowTheirAltitudeBias) {
  VegetationSettings v = testVegetation(3000, 11);
  v.conifer = {0.5, 2.0, 90.0, -1e4, 1e4, 1.0, 0.0, 0.0};
  v.broadleaf = {0.5, 2.0, 90.0, -1e4, 1e4, -1.0, 0.0, 0.0};
  const Forest f(v, testTerrain());
  ASSERT_EQ(f.trees().size(), 3000u);
  const Aabb ground = testTerrain().bounds();
  std::array<double, 5> sumA{}, conifers{}, trees{};
  for (const TreeInstance& t : f.trees()) {
    const double a = std::clamp((t.position.y - ground.min.y) / (ground.max.y - ground.min.y), 0.0, 1.0);
    const size_t bin = std::min<size_t>(4, static_cast<size_t>(a * 5.0));
    sumA[bin] += a;
    trees[bin] += 1.0;
    conifers[bin] += t.species == Species::Conifer ? 1.0 : 0.0;
  }
  int checked = 0;
  for (size_t b = 0; b < 5; ++b) {
    if (trees[b] < 50.0) continue;  // too few trees at that altitude to say anything
    const double p = sumA[b] / trees[b], share = conifers[b] / trees[b];
    EXPECT_NEAR(share, p, 4.0 * std::sqrt(p * (1.0 - p) / trees[b]) + 0.02) << "altitude fifth " << b << ", " << trees[b] << " trees";
    ++checked;
  }
  EXPECT_GE(checked, 3);
}

// Size classes: counts by their shares (4 binomial standard deviations), each tree's scale is its
// class's factor × a draw from scale_range, spacing shrinks with the class (young trees stand
// closer), and a young tree never takes LOD0 while an old one keeps LOD0 farther than a mature one.
TEST(TreePlacement, SizeClassesSetScaleSpacingAndLod) {
  VegetationSettings v = testVegetation(1500, 13);
  v.sizes = SizeClassSettings{{0.3, 0.5, 0.2}, {0.5, 1.0, 1.5}};
  const Forest f(v, testTerrain());
  ASSERT_EQ(f.trees().size(), 1500u);
  std::array<int, 3> counts{};
  for (std::uint32_t i = 0; i < f.trees().size(); ++i) {
    const TreeInstance& t = f.trees()[i];
    const int c = static_cast<int>(t.size);
    ++counts[static_cast<size_t>(c)];
    const double factor = v.sizes.scale[c];
    EXPECT_GE(t.scale, factor * v.scale_range.x - 1e-12) << i;
    EXPECT_LE(t.scale, factor * v.scale_range.y + 1e-12) << i;
    const dvec3 eye = t.position + dvec3(0.0, 1.7, 1.0);  // 1 m away: LOD0 for all but the young
    EXPECT_EQ(f.lodFor(i, eye), t.size == SizeClass::Young ? 1 : 0) << i;
    // 70 m: beyond the first band (60 m) for mature trees, inside it (× 1.5 = 90 m) for old ones.
    EXPECT_EQ(f.lodFor(i, t.position + dvec3(70.0, 0.0, 0.0)), t.size == SizeClass::Old ? 0 : 1) << i;
  }
  for (int c = 0; c < 3; ++c) {
    const double p = v.sizes.share[c];
    EXPECT_NEAR(counts[static_cast<size_t>(c)] / 1500.0, p, 4.0 * std::sqrt(p * (1.0 - p) / 1500.0)) << "class " << c;
  }
  for (size_t i = 0; i < f.trees().size(); ++i)
    for (size_t j = i + 1; j < f.trees().size(); ++j) {
      const TreeInstance &a = f.trees()[i], &b = f.trees()[j];
      const auto spacing = [&](const TreeInstance& t) {
        return (t.species == Species::Conifer ? v.conifer : v.broadleaf).spacing * v.sizes.scale[static_cast<int>(t.size)];
      };
      ASSERT_GE(glm::distance(glm::dvec2(a.position.x, a.position.z), glm::dvec2(b.position.x, b.position.z)),
                std::max(spacing(a), spacing(b)) - 1e-9)
          << i << ", " << j;
    }
}

TEST(TreePlacement, ReportsTheMostThatFit) {
  VegetationSettings v = testVegetation(100000);
  v.conifer.spacing = v.broadleaf.spacing = 12.0;
  const Forest f(v, testTerrain());
  EXPECT_LT(f.trees().size(), 100000u);
  EXPECT_GT(f.trees().size(), 500u);  // 0.25 km² at 12 m spacing holds well over 500
  EXPECT_EQ(f.requestedCount(), 100000);
}

TEST(TreePlacement, SameSeedIdenticalOtherSeedDiffers) {
  const Forest a(testVegetation(300, 9), testTerrain()), b(testVegetation(300, 9), testTerrain());
  const Forest c(testVegetation(300, 10), testTerrain());
  ASSERT_EQ(a.trees().size(), b.trees().size());
  for (size_t i = 0; i < a.trees().size(); ++i) {
    EXPECT_EQ(a.trees()[i].position, b.trees()[i].position);
    EXPECT_EQ(a.trees()[i].yaw, b.trees()[i].yaw);
  }
  EXPECT_NE(a.trees()[0].position, c.trees()[0].position);
}

TEST(TreeClusters, HoldSixteenToSixtyFourTreesInsideTheirBoxes) {
  const Forest& f = sharedForest();
  std::vector<int> seen(f.trees().size(), 0);
  for (const TreeCluster& c : f.clusters()) {
    EXPECT_GE(c.trees.size(), static_cast<size_t>(kMinClusterSize));
    EXPECT_LE(c.trees.size(), static_cast<size_t>(kMaxClusterSize));
    for (std::uint32_t t : c.trees) {
      ++seen[t];
      const Aabb box = f.treeBounds(t);
      EXPECT_TRUE(c.bounds.contains(box.min) && c.bounds.contains(box.max));
    }
  }
  for (int s : seen) EXPECT_EQ(s, 1);
}

TEST(TreeWind, EveryVertexOfASwayingTreeStaysInItsBox) {
  const Forest& f = sharedForest();
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> time(0.0, 1000.0);
  std::uniform_int_distribution<std::uint32_t> pick(0, static_cast<std::uint32_t>(f.trees().size() - 1));
  double largestShift = 0.0;
  for (int k = 0; k < 200; ++k) {
    const std::uint32_t tree = pick(rng);
    const double t = time(rng);
    const glm::dmat4 m = f.treeTransform(tree, t), still = f.treeTransform(tree, -1e9);
    const Aabb box = f.treeBounds(tree);
    for (int lod = 0; lod < kTreeLods; ++lod)
      for (const glm::vec3& p : f.model(f.trees()[tree].species).lods[lod].positions) {
        const dvec3 world(m * glm::dvec4(dvec3(p), 1.0));
        ASSERT_TRUE(box.contains(world, 1e-9)) << "tree " << tree << " at t = " << t;
        largestShift = std::max(largestShift, glm::distance(world, dvec3(still * glm::dvec4(dvec3(p), 1.0))));
      }
    // Same (tree, time) → same transform: the sway is a pure function.
    EXPECT_EQ(f.treeTransform(tree, t), m);
  }
  EXPECT_GT(largestShift, 0.1);  // the trees do sway
}

// How far a tree's vertices can sway in dt (what cached shadow slices wait on): no vertex moves
// between t and t + dt by more than its height above the base times windShearChangeBound — checked
// on the real transforms of sampled trees, vertices and times, for frame steps and long waits.
TEST(TreeWind, NoVertexSwaysFartherThanTheBoundInATimeStep) {
  const Forest& f = sharedForest();
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> time(0.0, 1000.0);
  std::uniform_int_distribution<std::uint32_t> pick(0, static_cast<std::uint32_t>(f.trees().size() - 1));
  double tallest = 0.0;
  for (std::uint32_t t = 0; t < f.trees().size(); ++t) tallest = std::max(tallest, f.treeBounds(t).max.y - f.trees()[t].position.y);
  EXPECT_NEAR(f.tallestTree(), tallest, 1e-9);  // the box's top: the tallest tree's top above its base
  double closest = 0.0;  // the largest share of the bound a sampled move used
  for (double dt : {1.0 / 60.0, 1.0 / 30.0, 0.25, 5.0}) {
    const double bound = windShearChangeBound(f.settings(), dt);
    // never more than the sway's range, 2 · strength · |direction|
    EXPECT_LE(bound, 2.0 * f.settings().wind_strength * glm::length(f.settings().wind_direction) + 1e-15);
    for (int k = 0; k < 300; ++k) {
      const std::uint32_t tree = pick(rng);
      const double t = time(rng);
      const glm::dmat4 a = f.treeTransform(tree, t), b = f.treeTransform(tree, t + dt);
      const TreeMesh& mesh = f.model(f.trees()[tree].species).lods[0];
      for (size_t i = 0; i < mesh.positions.size(); i += 7) {
        const glm::dvec4 p(dvec3(mesh.positions[i]), 1.0);
        const double height = dvec3(a * p).y - f.trees()[tree].position.y;
        const double moved = glm::distance(dvec3(a * p), dvec3(b * p));
        ASSERT_LE(moved, bound * std::abs(height) + 1e-9) << "tree " << tree << " t " << t << " dt " << dt;
        if (height > 1.0) closest = std::max(closest, moved / (bound * height));
      }
    }
  }
  EXPECT_GT(closest, 0.5);  // and the bound is not far above what trees do
}

// The query slabs (what occlusion queries draw for a tree) hold every point of every triangle of
// every LOD at any time: the vertices, edge midpoints and centroids, swayed, each inside one of
// the tree's slab boxes. And they are tighter than the tree's box: their total volume is smaller.
TEST(TreeWind, EveryPointOfASwayingTreeStaysInItsQuerySlabs) {
  const Forest& f = sharedForest();
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> time(0.0, 1000.0);
  std::uniform_int_distribution<std::uint32_t> pick(0, static_cast<std::uint32_t>(f.trees().size() - 1));
  double slabVolume = 0.0, boxVolume = 0.0;
  for (int k = 0; k < 100; ++k) {
    const std::uint32_t tree = pick(rng);
    const double t = time(rng);
    const glm::dmat4 m = f.treeTransform(tree, t);
    const std::array<Aabb, kQuerySlabs> slabs = f.treeQueryBoxes(tree);
    auto inSomeSlab = [&](const dvec3& p) {
      return std::any_of(slabs.begin(), slabs.end(), [&](const Aabb& b) { return b.valid() && b.contains(p, 1e-9); });
    };
    for (int lod = 0; lod < kTreeLods; ++lod) {
      const TreeMesh& mesh = f.model(f.trees()[tree].species).lods[lod];
      for (size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
        const dvec3 a(m * glm::dvec4(dvec3(mesh.positions[mesh.indices[i]]), 1.0));
        const dvec3 b(m * glm::dvec4(dvec3(mesh.positions[mesh.indices[i + 1]]), 1.0));
        const dvec3 c(m * glm::dvec4(dvec3(mesh.positions[mesh.indices[i + 2]]), 1.0));
        for (const dvec3& p : {a, b, c, 0.5 * (a + b), 0.5 * (b + c), 0.5 * (c + a), (a + b + c) / 3.0})
          ASSERT_TRUE(inSomeSlab(p)) << "tree " << tree << " LOD " << lod << " triangle " << i / 3 << " at t = " << t;
      }
    }
    for (const Aabb& b : slabs)
      if (b.valid()) slabVolume += b.extent().x * b.extent().y * b.extent().z;
    const Aabb box = f.treeBounds(tree);
    boxVolume += box.extent().x * box.extent().y * box.extent().z;
  }
  std::printf("[query slabs] their volume is %.2f of the trees' boxes\n", slabVolume / boxVolume);
  EXPECT_LT(slabVolume, 0.9 * boxVolume);
}

TEST(TreeMoves, ReportTheClustersWhoseBoxesChanged) {
  Forest f(testVegetation(500), testTerrain());
  const std::uint32_t a = 3, b = 250;
  const std::vector<Forest::Move> moves = {{a, {10.0, -20.0}, 0.5}, {b, {-100.0, 80.0}, 1.0}};
  const std::vector<std::uint32_t> changed = f.moveTrees(moves);
  std::set<std::uint32_t> expected;
  for (std::uint32_t c = 0; c < f.clusters().size(); ++c)
    for (std::uint32_t t : f.clusters()[c].trees)
      if (t == a || t == b) expected.insert(c);
  EXPECT_EQ(std::set<std::uint32_t>(changed.begin(), changed.end()), expected);
  for (std::uint32_t c : changed) {
    for (std::uint32_t t : f.clusters()[c].trees) {
      const Aabb box = f.treeBounds(t);
      EXPECT_TRUE(f.clusters()[c].bounds.contains(box.min) && f.clusters()[c].bounds.contains(box.max));
    }
  }
  EXPECT_NEAR(f.trees()[a].position.y, testTerrain().heightAt(10.0, -20.0), 1e-12);
}

TEST(TreeLod, DistanceBandsFromTheEyeOnly) {
  const Forest& f = sharedForest();
  const dvec3 base = f.trees()[0].position;
  EXPECT_EQ(f.lodFor(0, base + dvec3(0, 2, 10)), 0);
  EXPECT_EQ(f.lodFor(0, base + dvec3(100, 2, 0)), 1);
  EXPECT_EQ(f.lodFor(0, base + dvec3(0, 2, 300)), 2);
  EXPECT_EQ(f.lodFor(0, base + dvec3(0, 2, 500)), 3);
  VegetationSettings v = testVegetation(50);
  v.force_lod0 = true;
  const Forest forced(v, testTerrain());
  EXPECT_EQ(forced.lodFor(0, forced.trees()[0].position + dvec3(0, 2, 5000)), 0);
}

// The landscape (data/scenes/landscape.toml) as its issue asks: ≥ 1 000 000 trees on ≥ 4 km × 4 km,
// stands on ≥ 40% at 600–1500 stems/ha (measured on a 500 m square of it placed alone: the density
// in stands is the count per area, the same on any part), and its walk: from under the canopy out
// across a clearing, up ≥ 40 m to a ridge whose view holds forest kilometres away.
TEST(LandscapeWalk, LeavesAStandCrossesAClearingAndClimbsToARidgeOverKilometresOfForest) {
  const Scene scene = loadScene(std::string(FOREST_REPO_DATA) + "/scenes/landscape.toml");
  ASSERT_TRUE(scene.terrain && scene.vegetation && scene.vegetation->stands);
  EXPECT_GE(scene.vegetation->count, 1000000);
  EXPECT_GE(scene.terrain->size, 4000.0);
  const terrain::Terrain terrain(*scene.terrain);
  VegetationSettings part = *scene.vegetation;
  const double side = 500.0, share = side * side / (scene.terrain->size * scene.terrain->size);
  part.area = glm::dvec4(-side / 2, -side / 2, side / 2, side / 2);
  part.count = static_cast<int>(scene.vegetation->count * share);
  part.trail.reset();
  const ForestStats stats = forestStats(Forest(part, terrain));
  EXPECT_GE(stats.stemsPerHaInStands, 600.0);
  EXPECT_LE(stats.stemsPerHaInStands, 1500.0);
  const double h = scene.terrain->size / 2 - 1.0;  // the whole landscape's field (the placement's area)
  const StandField stands(*scene.vegetation->stands, scene.vegetation->seed, {-h, -h}, {h, h});
  EXPECT_GE(stands.standShare(), 0.40);

  const CameraPath path = CameraPath::load(std::string(FOREST_REPO_DATA) + "/paths/landscape-walk.toml");
  ASSERT_TRUE(path.aboveGround());
  const CameraPose start = path.at(path.startTime()), end = path.at(path.endTime());
  EXPECT_GE(stands.density(start.position.x, start.position.z), 0.9);  // under the canopy
  double clearing = 0.0, lowest = 1e9;
  for (double t = path.startTime(); t <= path.endTime(); t += 0.1) {
    const CameraPose pose = path.at(t);
    if (stands.density(pose.position.x, pose.position.z) < 0.1) clearing += 0.1;
    lowest = std::min(lowest, terrain.heightAt(pose.position.x, pose.position.z));
  }
  EXPECT_GE(clearing, 10.0);
  const double ridge = terrain.heightAt(end.position.x, end.position.z);
  EXPECT_GE(ridge - lowest, 40.0);
  // The view from the ridge: terrain points 1–3 km away across the view's 60° that the eye sees
  // over the terrain (line of sight 10 m over the ground there, a tree's height): a quarter or more,
  // a third of those in stands.
  const dvec3 eye(end.position.x, ridge + end.position.y, end.position.z);
  int targets = 0, seen = 0, seenInStands = 0;
  for (double r = 1000.0; r <= 3000.0; r += 100.0)
    for (double a = -30.0; a <= 30.0; a += 5.0) {
      const double yaw = glm::radians(end.yaw_deg + a);
      const glm::dvec2 p(eye.x - r * std::sin(yaw), eye.z - r * std::cos(yaw));
      if (std::max(std::abs(p.x), std::abs(p.y)) > h) continue;
      ++targets;
      const double top = terrain.heightAt(p.x, p.y) + 10.0;
      bool visible = true;
      for (double f = 0.01; f < 1.0 && visible; f += 0.01)
        visible = terrain.heightAt(eye.x + (p.x - eye.x) * f, eye.z + (p.y - eye.z) * f) < eye.y + (top - eye.y) * f;
      seen += visible ? 1 : 0;
      seenInStands += visible && stands.density(p.x, p.y) >= 0.5 ? 1 : 0;
    }
  ASSERT_GT(targets, 100);
  EXPECT_GE(seen, targets / 4);
  EXPECT_GE(3 * seenInStands, seen);
  std::printf("[landscape] %.0f stems/ha in stands, cover %.2f; walk: %.1f s in clearings, up %.0f m; ridge view: %d of %d points 1-3 km "
              "seen, %d of them in stands\n",
              stats.stemsPerHaInStands, stands.standShare(), clearing, ridge - lowest, seen, targets, seenInStands);
}

}  // namespace
}  // namespace forest::vegetation

namespace forest::vegetation {
namespace {

TEST(ThesisDemo, PresetPlacesTheGridOfClosedConeAndRingTrees) {
  const Scene scene = loadScene(std::string(FOREST_REPO_DATA) + "/scenes/thesis-demo.toml");
  ASSERT_TRUE(scene.vegetation && scene.terrain);
  EXPECT_EQ(scene.terrain->size, 200.0);
  EXPECT_EQ(scene.terrain->height_max - scene.terrain->height_min, 15.0);
  EXPECT_EQ(scene.camera.above_ground.value_or(-1.0), 0.2);
  EXPECT_EQ(scene.camera.near, 0.1);
  EXPECT_EQ(scene.camera.far, 70.0);
  const terrain::Terrain terrain(*scene.terrain);
  const Forest forest(*scene.vegetation, terrain);
  ASSERT_EQ(forest.trees().size(), 101u * 101u);
  EXPECT_EQ(forest.requestedCount(), 101 * 101);
  for (const TreeInstance& t : forest.trees()) {
    ASSERT_GE(t.scale, 1.0);
    ASSERT_LE(t.scale, 5.0);
    ASSERT_NEAR(t.position.y, terrain.heightAt(t.position.x, t.position.z), 1e-9);
  }
  // One tree per grid cell: 200 m less the 1 m insets over 101 cells, jitter within ±40%.
  const double cell = 198.0 / 101.0;
  for (int i : {0, 57, 101 * 101 - 1}) {
    const TreeInstance& t = forest.trees()[static_cast<size_t>(i)];
    const double cx = -99.0 + (i % 101 + 0.5) * cell, cz = -99.0 + (i / 101 + 0.5) * cell;
    EXPECT_LE(std::abs(t.position.x - cx), 0.4 * cell + 1e-9) << i;
    EXPECT_LE(std::abs(t.position.z - cz), 0.4 * cell + 1e-9) << i;
  }
  // A tree's box holds its query hull too (which reaches past the cone's facets: the culler's
  // tests on the box must cover what a hull query draws).
  for (std::uint32_t i = 0; i < forest.trees().size(); i += 97) {
    const glm::dmat4 m = forest.treeTransform(i, -1e9);
    const Aabb box = forest.treeBounds(i);
    for (const glm::vec3& p : forest.model(forest.trees()[i].species).queryHull.positions)
      ASSERT_TRUE(box.contains(dvec3(m * glm::dvec4(dvec3(p), 1.0)), 1e-9)) << "tree " << i;
  }
  for (const SpeciesModel& model : forest.species())
    for (const TreeMesh& lod : model.lods) {
      EXPECT_EQ(lod.triangleCount(), kThesisTreeTriangles);
      EXPECT_EQ(lod.components, 2);  // the cone and the ring
      const MeshTopology topology = inspectMesh(lod);
      EXPECT_EQ(topology.boundaryEdges, 0);
      EXPECT_EQ(topology.nonManifoldEdges, 0);
      ASSERT_EQ(topology.componentVolumes.size(), 2u);
      // Cone π r² h / 3 and torus 2π² R r², times the facets' share of the circles: 32 slices keep
      // (32 / 2π)·sin(2π/32) = 99.4% of a circle's area, the ring's 8 sides 90.0% (and 32 segments 99.4%).
      auto polygonShare = [](int sides) { return sides / (2.0 * std::numbers::pi) * std::sin(2.0 * std::numbers::pi / sides); };
      const double cone = std::numbers::pi * 0.3 * 0.3 * 1.0 / 3.0 * polygonShare(32);
      const double torus = 2.0 * std::numbers::pi * std::numbers::pi * 0.3 * 0.05 * 0.05 * polygonShare(8) * polygonShare(32);
      EXPECT_NEAR(topology.componentVolumes[0] / cone, 1.0, 0.01);
      EXPECT_NEAR(topology.componentVolumes[1] / torus, 1.0, 0.02);
    }
}

}  // namespace
}  // namespace forest::vegetation

namespace forest::vegetation {
namespace {

// The thesis tree's query hull (SpeciesModel::queryHull): two closed, outward pieces — a 16-sided
// pyramid circumscribed about the cone grown by the margin (inscribed radius 0.3 + 2m at y = −m,
// apex at 1 + 2m) and a 16-sided prism about the ring (inscribed radius 0.35 + m, y from 0.25 − m
// to 0.35 + m) — with the volumes of those solids, and every triangle of every LOD inside one piece.
// The same hull shrunk by 1% about the axis no longer holds the tree.
TEST(ThesisDemo, QueryHullHoldsEveryTriangleOfTheTreeInOnePiece) {
  for (Species species : {Species::Conifer, Species::Broadleaf}) {
    const SpeciesModel model = buildThesisTree(species);
    const TreeMesh& hull = model.queryHull;
    EXPECT_EQ(hull.triangleCount(), 90);
    ASSERT_EQ(hull.components, 2);
    const MeshTopology topology = inspectMesh(hull);
    EXPECT_EQ(topology.boundaryEdges, 0);
    EXPECT_EQ(topology.nonManifoldEdges, 0);
    ASSERT_EQ(topology.componentVolumes.size(), 2u);
    const double m = kThesisHullMargin, n = kThesisHullSides;
    const double polygonArea = n * std::tan(std::numbers::pi / n);  // × r² for the inscribed radius r
    EXPECT_NEAR(topology.componentVolumes[0], polygonArea * (0.3 + 2 * m) * (0.3 + 2 * m) * (1.0 + 3 * m) / 3.0, 1e-6);
    EXPECT_NEAR(topology.componentVolumes[1], polygonArea * (0.35 + m) * (0.35 + m) * (0.1 + 2 * m), 1e-6);
    for (const TreeMesh& lod : model.lods) EXPECT_TRUE(insideQueryHull(lod, hull));
    TreeMesh shrunk = hull;
    for (glm::vec3& p : shrunk.positions) p = glm::vec3(0.99f * p.x, p.y, 0.99f * p.z);
    EXPECT_FALSE(insideQueryHull(model.lods[0], shrunk));
  }
  // The procedural species have none: their crowns' gaps would be wrapped (geometry queries use
  // their own triangles).
  EXPECT_TRUE(buildSpecies(Species::Conifer, 2000, 7).queryHull.indices.empty());
}

}  // namespace
}  // namespace forest::vegetation

namespace forest::vegetation {
namespace {

// The default walk (data/paths/walk.toml over data/scenes/forest.toml), sampled every 0.1 s: it
// loads with heights over the ground; it starts outside a stand (D < 1/2) and is in one within
// 3 s; it spends ≥ 10 s in stands (issue "A forest to walk through"); the terrain within 0.3 m of
// the eye (the near plane's corners are 0.24 m away) stays 1 m below it; after the stands it
// climbs ≥ 25 m from its lowest ground to the end (the ridge), where it looks down.
TEST(DefaultWalk, StartsAtAStandsEdgeWalksUnderTheCanopyAndEndsOnTheRidge) {
  const Scene scene = loadScene(std::string(FOREST_REPO_DATA) + "/scenes/forest.toml");
  const CameraPath path = CameraPath::load(std::string(FOREST_REPO_DATA) + "/paths/walk.toml");
  ASSERT_TRUE(path.aboveGround());
  const terrain::Terrain terrain(*scene.terrain);
  const Forest forest(*scene.vegetation, terrain);
  ASSERT_NE(forest.stands(), nullptr);
  const StandField& stands = *forest.stands();
  constexpr double kStep = 0.1;
  double inStands = 0.0, firstInStand = -1.0, lastInStand = -1.0, lowestAfter = 1e9;
  for (double t = path.startTime(); t <= path.endTime() + 1e-9; t += kStep) {
    const CameraPose pose = path.at(t);
    const double ground = terrain.heightAt(pose.position.x, pose.position.z);
    const double eye = ground + pose.position.y;
    for (int k = 0; k < 8; ++k) {
      const double a = 2.0 * std::numbers::pi * k / 8.0;
      ASSERT_LT(terrain.heightAt(pose.position.x + 0.3 * std::cos(a), pose.position.z + 0.3 * std::sin(a)), eye - 1.0) << "t = " << t;
    }
    if (stands.density(pose.position.x, pose.position.z) >= 0.5) {
      inStands += kStep;
      if (firstInStand < 0.0) firstInStand = t;
      lastInStand = t;
      lowestAfter = 1e9;
    } else if (lastInStand >= 0.0) {
      lowestAfter = std::min(lowestAfter, ground);
    }
  }
  const CameraPose start = path.at(path.startTime()), end = path.at(path.endTime());
  EXPECT_LT(stands.density(start.position.x, start.position.z), 0.5);
  EXPECT_GE(firstInStand, 0.0);
  EXPECT_LE(firstInStand, path.startTime() + 3.0);
  EXPECT_GE(inStands, 10.0);
  const double endGround = terrain.heightAt(end.position.x, end.position.z);
  EXPECT_GE(endGround - lowestAfter, 25.0);
  EXPECT_LT(end.pitch_deg, 0.0);
  std::printf("[walk] %.1f s in stands of %.1f s (first at %.1f s, last at %.1f s); then down to %.1f m and up to the ridge at %.1f m\n",
              inStands, path.endTime() - path.startTime(), firstInStand, lastInStand, lowestAfter, endGround);
}

}  // namespace
}  // namespace forest::vegetation
