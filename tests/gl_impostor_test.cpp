// Far trees' impostors (render/impostor_atlas.hpp): the bake against the mesh it was baked from,
// traced by Embree from the bake's own views — coverage against the mesh's silhouette, and the
// viewer's and the far side's depths within what the surface spans across one texel.
#include <algorithm>
#include <cmath>
#include <array>
#include <optional>
#include <cstdio>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "forest/raytrace/ray_scene.hpp"
#include "forest/render/draw_view.hpp"
#include "forest/render/impostor_atlas.hpp"
#include "forest/render/tree_renderer.hpp"
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

// The entry of the line a + s·d (s ≥ sMin) into the box, or none.
std::optional<double> boxEntry(const Aabb& box, const glm::dvec3& a, const glm::dvec3& d, double sMin) {
  double enter = sMin, leave = 1e300;
  for (int k = 0; k < 3; ++k) {
    if (d[k] == 0.0) {
      if (a[k] < box.min[k] || a[k] > box.max[k]) return std::nullopt;
      continue;
    }
    const double s0 = (box.min[k] - a[k]) / d[k], s1 = (box.max[k] - a[k]) / d[k];
    enter = std::max(enter, std::min(s0, s1));
    leave = std::min(leave, std::max(s0, s1));
  }
  if (enter > leave) return std::nullopt;
  return enter;
}

// 60 trees of the default scene without wind (impostors do not sway: the boxes and slabs as drawn)
// and their impostors' bake.
struct StillTrees {
  Scene scene = loadScene(std::string(FOREST_REPO_DATA) + "/scenes/forest.toml");
  terrain::Terrain terrain{*scene.terrain};
  vegetation::Forest forest{stillSettings(scene), terrain};
  render::ImpostorAtlas atlas{forest};
  static VegetationSettings stillSettings(const Scene& scene) {
    VegetationSettings settings = *scene.vegetation;
    settings.count = 60;
    settings.wind_strength = 0.0;
    return settings;
  }
};

// An impostor writes only inside the volumes the exact tests take for its tree, never nearer than
// where the fragment's line enters them: seen by the eye, the pixel's ray meets the tree's query
// boxes (Forest::treeQueryBoxes, what the culler asks) no farther than the depth written; seen from
// the sun, the texel's line meets its crown slabs (Forest::placedCasterSlabs, what the caster tests
// take) no farther than the light depth written. Every species from 36 directions each, between the
// bake views (where the bake's parallax is largest), at 40 m and from the sun at 3 elevations.
TEST_F(ImpostorGl, AnImpostorStaysInsideItsQueryBoxesAndCrownSlabs) {
  const StillTrees still;
  const Scene& scene = still.scene;
  const vegetation::Forest& forest = still.forest;
  const render::ImpostorAtlas& atlas = still.atlas;
  render::TreeRenderer trees(forest, render::SurfaceOutput::ObjectId, 1);
  trees.setImpostors(&atlas, {1.0, 0.0});  // every tree 1 m away or more: its impostor
  const int size = 200;
  const IdDepthTarget target(size, size);
  long long eyePixels = 0, eyeOutside = 0, sunTexels = 0, sunOutside = 0;
  for (vegetation::Species species : vegetation::kAllSpecies) {
    std::uint32_t tree = 0;
    while (tree < forest.trees().size() && forest.trees()[tree].species != species) ++tree;
    ASSERT_LT(tree, forest.trees().size());
    const std::uint32_t drawn[] = {tree};
    const glm::dvec3 centre = forest.treeBounds(tree).centre();
    const std::array<Aabb, vegetation::kQuerySlabs> boxes = forest.treeQueryBoxes(tree);
    std::vector<vegetation::PlacedCrownSlab> slabs;
    forest.placedCasterSlabs(tree, slabs);
    for (int k = 0; k < 36; ++k) {
      const double azimuth = glm::radians(7.0 + 30.0 * (k % 12)), elevation = glm::radians(3.0 + 17.0 * (k / 12));
      const glm::dvec3 toViewer(std::cos(elevation) * std::cos(azimuth), std::sin(elevation), std::cos(elevation) * std::sin(azimuth));
      // The eye, 40 m out.
      Camera camera;
      camera.position = centre + 40.0 * toViewer;
      camera.orient(centre - camera.position, glm::dvec3(0.0, 1.0, 0.0));
      camera.aspect = 1.0;
      camera.near = 1.0;
      camera.far = 200.0;
      target.bindAndClear();
      trees.draw(render::DrawView::fromCamera(camera, 0.0, scene.sun), drawn);
      const std::vector<std::uint32_t> ids = target.readIds();
      const std::vector<float> depth = target.readDepth();
      for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
          const size_t p = static_cast<size_t>(y) * size + x;
          if (ids[p] == 0) continue;
          ++eyePixels;
          const glm::dvec3 at = pixelPosition(camera, x, y, depth[p], size, size);
          const glm::dvec3 ray = at - camera.position;
          std::optional<double> entry;
          for (const Aabb& box : boxes)
            if (const std::optional<double> e = boxEntry(box, camera.position, ray, 0.0)) entry = std::min(entry.value_or(1e300), *e);
          eyeOutside += !entry || *entry > 1.0 + 1e-5 ? 1 : 0;  // at s = 1 the written depth
        }
      // The sun: an orthographic view along −toViewer, depth 0 nearest the sun.
      const glm::dmat4 light = glm::orthoRH_ZO(-25.0, 25.0, -25.0, 25.0, 0.0, 200.0) *
                               glm::lookAt(centre + 100.0 * toViewer, centre, glm::dvec3(0.0, 1.0, 0.0));
      render::DrawView sun = render::DrawView::fromCamera(camera, 0.0, scene.sun);
      sun.sun.direction = -toViewer;
      sun.fromSun = true;
      sun.origin = centre;
      sun.viewProjectionRelative = light * glm::translate(glm::dmat4(1.0), centre);
      target.bindAndClear();
      glClearDepth(1.0);
      glClear(GL_DEPTH_BUFFER_BIT);
      glDepthFunc(GL_LESS);
      trees.draw(sun, drawn);
      const std::vector<std::uint32_t> texelIds = target.readIds();
      const std::vector<float> lightDepth = target.readDepth();
      glDepthFunc(GL_GREATER);
      const glm::dmat4 toWorld = glm::inverse(light);
      for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
          const size_t p = static_cast<size_t>(y) * size + x;
          if (texelIds[p] == 0) continue;
          ++sunTexels;
          const glm::dvec2 ndc(2.0 * (x + 0.5) / size - 1.0, 2.0 * (y + 0.5) / size - 1.0);
          const glm::dvec3 a = glm::dvec3(toWorld * glm::dvec4(ndc, 0.0, 1.0)), b = glm::dvec3(toWorld * glm::dvec4(ndc, 1.0, 1.0));
          std::optional<double> entry;  // as a light depth, 0 … 1 from a to b
          for (const vegetation::PlacedCrownSlab& slab : slabs)
            if (const std::optional<glm::dvec2> span = slab.lineSpan(a, b - a, 0.0)) entry = std::min(entry.value_or(1e300), span->x);
          sunOutside += !entry || *entry > lightDepth[p] + 1e-5 ? 1 : 0;
        }
    }
  }
  std::printf("[impostor volumes] %lld eye pixels, %lld outside the query boxes or nearer than their entry; %lld sun texels, %lld "
              "outside the crown slabs or nearer than their entry\n", eyePixels, eyeOutside, sunTexels, sunOutside);
  EXPECT_GT(eyePixels, 30000);
  EXPECT_GT(sunTexels, 30000);
  EXPECT_EQ(eyeOutside, 0);
  EXPECT_EQ(sunOutside, 0);
}

// A lone tree's shadow from its impostor against its mesh's, traced by Embree: with the sun along
// one of the bake's views (so the bake's angle to the sun is 0 and only the texels differ), the
// impostor covers a light-view texel exactly where the mesh's traced silhouette does, but within a
// bake texel's half diagonal (scaled to the tree) plus a map texel's of the silhouette's edge.
TEST_F(ImpostorGl, ALoneImpostorsShadowIsItsMeshsWithinATexelOfTheEdge) {
  const StillTrees still;
  const Scene& scene = still.scene;
  const vegetation::Forest& forest = still.forest;
  const render::ImpostorAtlas& atlas = still.atlas;
  render::TreeRenderer trees(forest, render::SurfaceOutput::ObjectId, 1);
  trees.setImpostors(&atlas, {1.0, 0.0});
  const int size = 256;
  const IdDepthTarget target(size, size);
  long long shadowTexels = 0, wrong = 0, wrongNearEdge = 0;
  for (vegetation::Species species : vegetation::kAllSpecies) {
    std::uint32_t tree = 0;
    while (tree < forest.trees().size() && forest.trees()[tree].species != species) ++tree;
    const vegetation::TreeInstance& t = forest.trees()[tree];
    const std::uint32_t drawn[] = {tree};
    raytrace::RayScene rays;
    const vegetation::TreeMesh& mesh = forest.model(species).lods[0];
    rays.addInstance(rays.addMesh(mesh.positions, mesh.indices), forest.treeTransform(tree, 0.0), 1);
    rays.commit();
    const double extent = 1.1 * atlas.sphere(species).radius * t.scale;  // the light view's half width
    const double mapTexel = 2.0 * extent / size, bakeTexel = 2.0 * atlas.sphere(species).radius * t.scale / atlas.texelsPerView();
    const double edgeBand = std::sqrt(0.5) * (mapTexel + bakeTexel);
    const glm::dvec3 centre = glm::dvec3(forest.treeTransform(tree, 0.0) * glm::dvec4(atlas.sphere(species).centre, 1.0));
    for (const glm::ivec2 view : {glm::ivec2(3, 12), glm::ivec2(6, 9), glm::ivec2(10, 4)}) {
      // The bake view's direction in the world: rotated by the tree's yaw (Forest::treeTransform).
      const glm::dvec3 toSun = glm::dvec3(glm::rotate(glm::dmat4(1.0), t.yaw, glm::dvec3(0.0, 1.0, 0.0)) *
                                          glm::dvec4(atlas.grid().frame(view.x, view.y).toViewer, 0.0));
      const glm::dvec3 side = glm::normalize(glm::cross(glm::dvec3(0.0, 1.0, 0.0), toSun)), up = glm::cross(toSun, side);
      const glm::dmat4 light = glm::orthoRH_ZO(-extent, extent, -extent, extent, 0.0, 400.0) * glm::lookAt(centre + 200.0 * toSun, centre, up);
      render::DrawView sun;
      sun.sun = scene.sun;
      sun.sun.direction = -toSun;
      sun.fromSun = true;
      sun.origin = centre;
      sun.lodEye = centre + glm::dvec3(1000.0, 0.0, 0.0);
      sun.viewProjectionRelative = light * glm::translate(glm::dmat4(1.0), centre);
      target.bindAndClear();
      glClearDepth(1.0);
      glClear(GL_DEPTH_BUFFER_BIT);
      glDepthFunc(GL_LESS);
      trees.draw(sun, drawn);
      glDepthFunc(GL_GREATER);
      const std::vector<std::uint32_t> ids = target.readIds();
      // The mesh's shadow: each texel's line toward the sun meets the mesh.
      std::vector<std::uint8_t> traced(ids.size());
      for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
          const glm::dvec3 at = centre + (-extent + (x + 0.5) * mapTexel) * side + (-extent + (y + 0.5) * mapTexel) * up + 200.0 * toSun;
          traced[static_cast<size_t>(y) * size + x] = rays.occluded(at, -toSun) ? 1 : 0;
        }
      const int reach = static_cast<int>(std::ceil(edgeBand / mapTexel));
      for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
          const size_t p = static_cast<size_t>(y) * size + x;
          shadowTexels += traced[p];
          if ((ids[p] != 0) == (traced[p] != 0)) continue;
          // Within edgeBand of a texel the trace puts on the other side?
          bool nearEdge = false;
          for (int dy = -reach; dy <= reach && !nearEdge; ++dy)
            for (int dx = -reach; dx <= reach && !nearEdge; ++dx) {
              const int nx = x + dx, ny = y + dy;
              if (nx < 0 || ny < 0 || nx >= size || ny >= size || std::hypot(dx, dy) * mapTexel > edgeBand + mapTexel) continue;
              nearEdge = traced[static_cast<size_t>(ny) * size + nx] != traced[p];
            }
          (nearEdge ? wrongNearEdge : wrong) += 1;
        }
    }
  }
  std::printf("[impostor shadow] %lld texels of mesh shadow traced; the impostor's differs at %lld within a texel of the edge, %lld "
              "farther\n", shadowTexels, wrongNearEdge, wrong);
  EXPECT_GT(shadowTexels, 20000);
  EXPECT_EQ(wrong, 0);
}

// The cross-fade's share against its closed form: 0 up to the switch distance, rising linearly to 1
// over the band, 1 beyond — continuous in distance (no step larger than the slope times the step).
TEST(ImpostorSwitch, TheImpostorsShareRisesContinuouslyOverTheBand) {
  const render::ImpostorSwitch s{600.0, 0.1};
  EXPECT_EQ(render::impostorShare(s, 0.0), 0.0);
  EXPECT_EQ(render::impostorShare(s, 600.0), 0.0);
  EXPECT_DOUBLE_EQ(render::impostorShare(s, 630.0), 0.5);
  EXPECT_EQ(render::impostorShare(s, 660.0), 1.0);
  EXPECT_EQ(render::impostorShare(s, 1e6), 1.0);
  double previous = 0.0;
  for (double d = 0.0; d <= 1000.0; d += 0.01) {
    const double share = render::impostorShare(s, d);
    ASSERT_LE(std::abs(share - previous), 0.01 / 60.0 + 1e-12) << d;
    ASSERT_GE(share, previous) << d;
    previous = share;
  }
  EXPECT_EQ(render::impostorShare({0.0, 0.1}, 1e6), 0.0);  // off
  EXPECT_EQ(render::impostorShare({600.0, 0.0}, 599.0), 0.0);  // no band: a step
  EXPECT_EQ(render::impostorShare({600.0, 0.0}, 600.0), 1.0);
}

// In the band both representations draw the tree with complementary dither: every pixel that the
// mesh alone and the impostor alone both cover is written by exactly one of them (so covered), and
// nothing outside what either covers is.
TEST_F(ImpostorGl, TheCrossFadeCoversWhatBothRepresentationsCover) {
  const StillTrees still;
  const Scene& scene = still.scene;
  const vegetation::Forest& forest = still.forest;
  const render::ImpostorAtlas& atlas = still.atlas;
  render::TreeRenderer trees(forest, render::SurfaceOutput::ObjectId, 1);
  const int size = 200;
  const IdDepthTarget target(size, size);
  long long both = 0, bothMissed = 0, fadeOutside = 0, fadeCovered = 0;
  for (std::uint32_t tree = 0; tree < 6; ++tree) {
    const std::uint32_t drawn[] = {tree};
    Camera camera;
    const glm::dvec3 centre = forest.treeBounds(tree).centre();
    camera.position = centre + 25.0 * glm::normalize(glm::dvec3(std::cos(tree), 0.3, std::sin(tree)));
    camera.orient(centre - camera.position, glm::dvec3(0.0, 1.0, 0.0));
    camera.aspect = 1.0;
    camera.near = 1.0;
    camera.far = 300.0;
    const double distance = forest.lodDistance(tree, camera.position);
    auto idsWith = [&](render::ImpostorSwitch s) {
      trees.setImpostors(&atlas, s);
      target.bindAndClear();
      trees.draw(render::DrawView::fromCamera(camera, 0.0, scene.sun), drawn);
      return target.readIds();
    };
    const std::vector<std::uint32_t> mesh = idsWith({1e5, 0.1}), impostor = idsWith({1.0, 0.0});
    const std::vector<std::uint32_t> fade = idsWith({distance / 1.05, 0.1});  // share 0.5
    for (size_t p = 0; p < mesh.size(); ++p) {
      const bool m = mesh[p] != 0, i = impostor[p] != 0, f = fade[p] != 0;
      both += m && i ? 1 : 0;
      bothMissed += m && i && !f ? 1 : 0;
      fadeOutside += f && !m && !i ? 1 : 0;
      fadeCovered += f ? 1 : 0;
    }
  }
  std::printf("[cross-fade] %lld pixels covered by both representations, %lld of them missed in the cross-fade; %lld written "
              "outside both\n", both, bothMissed, fadeOutside);
  EXPECT_GT(both, 10000);
  EXPECT_GT(fadeCovered, 10000);
  EXPECT_EQ(bothMissed, 0);
  EXPECT_EQ(fadeOutside, 0);
}

}  // namespace
}  // namespace forest::test
