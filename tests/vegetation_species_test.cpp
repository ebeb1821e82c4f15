// Tree species: every LOD of every species is a union of closed, 2-manifold, outward-oriented
// components without self-intersections (ray parity with Embree), at its triangle target.
#include <gtest/gtest.h>

#include <cstring>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "forest/core/error.hpp"
#include "forest/raytrace/ray_scene.hpp"
#include "forest/vegetation/species.hpp"

namespace forest::vegetation {
namespace {

using glm::dvec3;

const SpeciesModel& model(Species species, int budget) {
  static std::map<std::pair<int, int>, SpeciesModel> cache;
  const auto key = std::make_pair(static_cast<int>(species), budget);
  if (!cache.count(key)) cache.emplace(key, buildSpecies(species, budget, 20061125));
  return cache.at(key);
}

constexpr auto& kSpecies = kAllSpecies;

TEST(TreeSpecies, EveryLodIsClosedManifoldAndOutward) {
  for (Species species : kSpecies) {
    for (int budget : {1000, 2000}) {
      const SpeciesModel& m = model(species, budget);
      for (int lod = 0; lod < kTreeLods; ++lod) {
        const TreeMesh& mesh = m.lods[lod];
        const MeshTopology t = inspectMesh(mesh);
        const std::string where = std::string(speciesName(species)) + " budget " + std::to_string(budget) + " LOD" + std::to_string(lod);
        EXPECT_EQ(t.boundaryEdges, 0) << where;
        EXPECT_EQ(t.nonManifoldEdges, 0) << where;
        EXPECT_GT(t.signedVolume, 0.0) << where;
        ASSERT_EQ(t.componentVolumes.size(), static_cast<size_t>(mesh.components)) << where;
        for (double v : t.componentVolumes) EXPECT_GT(v, 0.0) << where;
        // trunk + five cones; trunk, three branches and seven blobs; three stems and five blobs
        const int parts = species == Species::Conifer ? 6 : species == Species::Broadleaf ? 11 : 8;
        EXPECT_GE(mesh.components, parts) << where;
      }
    }
  }
}

TEST(TreeSpecies, TriangleCountsWithinFifteenPercentOfTheTarget) {
  for (Species species : kSpecies) {
    for (int budget : {1000, 2000, 20000}) {
      const SpeciesModel& m = model(species, budget);
      for (int lod = 0; lod < kTreeLods; ++lod) {
        const double ratio = static_cast<double>(m.lods[lod].triangleCount()) / m.targetTriangles[lod];
        EXPECT_NEAR(ratio, 1.0, 0.15) << speciesName(species) << " budget " << budget << " LOD" << lod << ": "
                                      << m.lods[lod].triangleCount() << " for " << m.targetTriangles[lod];
      }
      EXPECT_TRUE(inspectMesh(m.lods[0]).boundaryEdges == 0);
    }
  }
  EXPECT_THROW(buildSpecies(Species::Conifer, 999, 1), InputError);
  EXPECT_THROW(buildSpecies(Species::Conifer, 20001, 1), InputError);
}

TEST(TreeSpecies, SameSeedIdenticalOtherSeedDiffers) {
  const SpeciesModel a = buildSpecies(Species::Broadleaf, 2000, 5), b = buildSpecies(Species::Broadleaf, 2000, 5);
  const SpeciesModel c = buildSpecies(Species::Broadleaf, 2000, 6);
  ASSERT_EQ(a.lods[0].positions.size(), b.lods[0].positions.size());
  EXPECT_EQ(std::memcmp(a.lods[0].positions.data(), b.lods[0].positions.data(), a.lods[0].positions.size() * sizeof(glm::vec3)), 0);
  EXPECT_EQ(a.lods[0].indices, b.lods[0].indices);
  EXPECT_NE(a.lods[0].bounds.max, c.lods[0].bounds.max);
}

// Along a ray, the hits on one closed, outward, self-intersection-free component alternate
// entering (direction against the face normal) and leaving, starting outside and ending outside.
TEST(TreeSpecies, ComponentsDoNotIntersectThemselves) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int rays = 0, crossings = 0, dropped = 0;
  for (Species species : kSpecies) {
    for (int lod = 0; lod < kTreeLods; ++lod) {
      const TreeMesh& mesh = model(species, 2000).lods[lod];
      for (int component = 0; component < mesh.components; ++component) {
        std::vector<std::uint32_t> indices;
        Aabb box;
        for (size_t f = 0; f < mesh.faceComponent.size(); ++f) {
          if (mesh.faceComponent[f] != static_cast<std::uint32_t>(component)) continue;
          for (int k = 0; k < 3; ++k) {
            indices.push_back(mesh.indices[3 * f + k]);
            box.extend(dvec3(mesh.positions[mesh.indices[3 * f + k]]));
          }
        }
        raytrace::RayScene scene;
        scene.addInstance(scene.addMesh(mesh.positions, indices), glm::dmat4(1.0), static_cast<std::uint32_t>(component));
        scene.commit();
        const double size = box.diagonal();
        for (int r = 0; r < 150; ++r, ++rays) {
          const double z = 2 * unit(rng) - 1, phi = 6.283185307 * unit(rng), s = std::sqrt(1 - z * z);
          const dvec3 origin = box.centre() + 2.0 * size * dvec3(s * std::cos(phi), z, s * std::sin(phi));
          const dvec3 target(box.min.x + unit(rng) * box.extent().x, box.min.y + unit(rng) * box.extent().y,
                             box.min.z + unit(rng) * box.extent().z);
          const dvec3 direction = glm::normalize(target - origin);
          int depth = 0, lastSign = 0;
          double t = 0.0, lastDistance = -1.0;
          bool grazes = false;
          std::vector<std::string> steps;
          for (int guard = 0; guard < 1000; ++guard) {
            const raytrace::RayHit hit = scene.intersect(origin, direction, t, 1e30);
            if (!hit.hit) break;
            // A ray within 1e-4 (barycentric) of an edge may touch a silhouette edge or pass
            // between float-rounded neighbours: its parity means nothing. Such rays are dropped.
            if (std::min({hit.u, hit.v, 1.0 - hit.u - hit.v}) < 1e-4) {
              grazes = true;
              break;
            }
            // Continue a few float ulps past this hit (Embree traces in float).
            t = hit.distance * (1.0 + 4e-7) + 1e-7;
            const dvec3 a(mesh.positions[indices[3 * hit.primitive]]), b(mesh.positions[indices[3 * hit.primitive + 1]]),
                c(mesh.positions[indices[3 * hit.primitive + 2]]);
            const int sign = glm::dot(glm::cross(b - a, c - a), direction) < 0.0 ? 1 : -1;
            // A ray through a shared edge or vertex reports each triangle there: one crossing.
            if (sign == lastSign && hit.distance - lastDistance < 1e-5 * size) continue;
            lastSign = sign;
            lastDistance = hit.distance;
            depth += sign;
            steps.push_back(std::to_string(hit.distance) + (sign > 0 ? " in" : " out"));
            if (depth != 0 && depth != 1) break;
          }
          if (grazes) {
            ++dropped;
            continue;
          }
          crossings += static_cast<int>(steps.size());
          std::string path;
          for (const std::string& step : steps) path += step + ", ";
          EXPECT_EQ(depth, 0) << speciesName(species) << " LOD" << lod << " component " << component << ": " << path;
        }
      }
    }
  }
  EXPECT_GT(crossings, rays);    // most rays do cross their component
  EXPECT_LT(dropped, rays / 50); // and few graze an edge
}

}  // namespace
}  // namespace forest::vegetation
