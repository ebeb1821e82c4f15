// Far trees' impostors (render/impostor_atlas.hpp): the bake against the mesh it was baked from,
// traced by Embree from the bake's own views — coverage against the mesh's silhouette, and the
// viewer's and the far side's depths within what the surface spans across one texel.
#include <algorithm>
#include <cstdio>
#include <vector>

#include "forest/raytrace/ray_scene.hpp"
#include "forest/render/impostor_atlas.hpp"
#include "gl_test_support.hpp"
#include "test_paths.hpp"

namespace forest::test {
namespace {

using vegetation::Species;

class ImpostorGl : public GlTest {};

// What Embree sees along a bake texel's line (from the bake plane, along −toViewer): the nearest
// surface and the nearest one turned away from the viewer (the faces each bake pass keeps).
struct TracedTexel {
  bool covered = false;
  double front = 0.0, back = 0.0;
};

TracedTexel trace(const raytrace::RayScene& rays, const glm::dvec3& origin, const glm::dvec3& direction) {
  TracedTexel t;
  double from = 0.0;
  for (int crossing = 0; crossing < 256; ++crossing) {
    const raytrace::RayHit hit = rays.intersect(origin, direction, from);
    if (!hit.hit) break;
    const bool facesViewer = glm::dot(hit.normal, direction) < 0.0;
    if (facesViewer && !t.covered) {
      t.covered = true;
      t.front = hit.distance;
    }
    if (!facesViewer) {
      t.back = hit.distance;
      if (!t.covered) t.covered = true, t.front = hit.distance;  // seen edge-on: both passes may keep it
      break;
    }
    from = hit.distance * (1.0 + 1e-6) + 1e-6;  // past the hit in float32, Embree's precision
  }
  return t;
}

// Every species' bake from a spread of its own views: a texel is covered where the line through its
// centre meets the mesh (rasterising and tracing sample the same centre), but for texels on the
// silhouette (a 3 × 3 neighbour the other way, where only a tie can differ), and each of its depths
// lies within the range traced across its footprint (3 × 3 lines) and at its neighbours' centres —
// within a texel's width of it where that range holds a depth edge.
TEST_F(ImpostorGl, TheBakeIsTheMeshSeenFromEachBakeView) {
  const Scene scene = loadScene(std::string(FOREST_REPO_DATA) + "/scenes/forest.toml");
  ASSERT_TRUE(scene.terrain && scene.vegetation);
  const terrain::Terrain terrain(*scene.terrain);
  VegetationSettings settings = *scene.vegetation;
  settings.count = 20;  // the species are what is baked
  const vegetation::Forest forest(settings, terrain);
  const render::ImpostorAtlas atlas(forest, 8, 32);
  const int views = atlas.grid().views(), texels = atlas.texelsPerView(), side = views * texels;
  std::printf("[impostor bake] %d species, %d × %d views of %d² texels in %.2f s\n", vegetation::kSpeciesCount, views, views, texels,
              atlas.bakeSeconds());
  for (Species species : vegetation::kAllSpecies) {
    const vegetation::TreeMesh& mesh = forest.model(species).lods[0];
    raytrace::RayScene rays;
    rays.addInstance(rays.addMesh(mesh.positions, mesh.indices), glm::dmat4(1.0), 1);
    rays.commit();
    const std::vector<glm::uvec4> layer = atlas.download(species);
    const double radius = atlas.sphere(species).radius;
    long long covered = 0, silhouette = 0, coverageWrong = 0, frontWrong = 0, backWrong = 0;
    for (int i = 0; i < views; i += 3)
      for (int j = 0; j < views; j += 2) {
        const vegetation::ImpostorFrame f = atlas.grid().frame(i, j);
        // Per texel its centre's line, and the depths met across its footprint (3 × 3 lines).
        std::vector<TracedTexel> traced(static_cast<size_t>(texels) * texels), spanLo(traced.size()), spanHi(traced.size());
        for (int y = 0; y < texels; ++y)
          for (int x = 0; x < texels; ++x) {
            const size_t k = static_cast<size_t>(y * texels + x);
            const glm::dvec2 centre(x + 0.5, y + 0.5);
            traced[k] = trace(rays, atlas.bakePoint(species, i, j, centre, 0.0), -f.toViewer);
            spanLo[k] = spanHi[k] = traced[k];
            for (int s = 0; s < 9; ++s) {
              const TracedTexel t = trace(rays, atlas.bakePoint(species, i, j, centre + 0.49 * glm::dvec2(s % 3 - 1, s / 3 - 1), 0.0), -f.toViewer);
              if (!t.covered) continue;
              if (!spanLo[k].covered) spanLo[k] = spanHi[k] = t;
              spanLo[k].front = std::min(spanLo[k].front, t.front), spanHi[k].front = std::max(spanHi[k].front, t.front);
              spanLo[k].back = std::min(spanLo[k].back, t.back), spanHi[k].back = std::max(spanHi[k].back, t.back);
            }
          }
        for (int y = 0; y < texels; ++y)
          for (int x = 0; x < texels; ++x) {
            const TracedTexel& t = traced[static_cast<size_t>(y * texels + x)];
            const render::ImpostorTexel b =
                render::unpackImpostorTexel(layer[static_cast<size_t>((j * texels + y) * side + i * texels + x)]);
            bool edge = false;
            const size_t k = static_cast<size_t>(y * texels + x);
            double frontLo = spanLo[k].front, frontHi = spanHi[k].front, backLo = spanLo[k].back, backHi = spanHi[k].back;
            for (int dy = -1; dy <= 1; ++dy)
              for (int dx = -1; dx <= 1; ++dx) {
                const int nx = x + dx, ny = y + dy;
                if (nx < 0 || ny < 0 || nx >= texels || ny >= texels) continue;
                const TracedTexel& n = traced[static_cast<size_t>(ny * texels + nx)];
                if (n.covered != t.covered) edge = true;
                if (!n.covered) continue;
                frontLo = std::min(frontLo, n.front), frontHi = std::max(frontHi, n.front);
                backLo = std::min(backLo, n.back), backHi = std::max(backHi, n.back);
              }
            covered += t.covered ? 1 : 0;
            silhouette += edge ? 1 : 0;
            if (b.covered != t.covered) {
              coverageWrong += edge ? 0 : 1;
              continue;
            }
            if (!t.covered || edge) continue;
            // Where the depths jump within the footprint (an edge in front of a farther surface), a
            // surface thinner than the lines' spacing (a twig) can lie between them: a texel's width
            // of slack there; elsewhere float32's over the bake's depth range.
            const double texel = 2.0 * radius / texels;
            auto slack = [&](double lo, double hi) { return hi - lo > texel ? texel : 1e-4 * radius; };
            const double frontSlack = slack(frontLo, frontHi), backSlack = slack(backLo, backHi);
            frontWrong += b.front < frontLo - frontSlack || b.front > frontHi + frontSlack ? 1 : 0;
            backWrong += b.back < backLo - backSlack || b.back > backHi + backSlack ? 1 : 0;
          }
      }
    std::printf("[impostor bake] %s: %lld covered texels traced, %lld on the silhouette; off the silhouette %lld coverage, "
                "%lld front and %lld back depths wrong\n",
                std::string(vegetation::speciesName(species)).c_str(), covered, silhouette, coverageWrong, frontWrong, backWrong);
    EXPECT_GT(covered, 1000);
    EXPECT_EQ(coverageWrong, 0);
    EXPECT_EQ(frontWrong, 0);
    EXPECT_EQ(backWrong, 0);
  }
}

}  // namespace
}  // namespace forest::test
