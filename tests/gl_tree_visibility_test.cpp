// Visibility per tree (DESIGN §4 culling/): each tree is an object of the culling hierarchy, and
// the visible trees are drawn by one instanced call per species × LOD. Checked on the GPU with
// counts from outside the culler: the triangles the draw generates (GL_PRIMITIVES_GENERATED)
// against the species meshes' triangle counts, and the trees in the object-ID image; and the
// trees chc++ draws with geometry queries against the trees in the brute-force ID image.
#include <algorithm>
#include <cstdio>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "forest/core/camera_path.hpp"
#include "forest/core/frustum.hpp"
#include "forest/core/scene.hpp"
#include "forest/culling/bvh.hpp"
#include "forest/culling/occlusion_culler.hpp"
#include "forest/gl/objects.hpp"
#include "forest/render/scene_objects.hpp"
#include "gl_test_support.hpp"
#include "test_paths.hpp"

namespace forest::test {
namespace {

using glm::dvec3;

constexpr int kWidth = 320, kHeight = 180;

class TreeVisibilityGl : public GlTest {};

// The triangles of a tree list at the eye's LODs, from the species meshes.
long long meshTriangles(const vegetation::Forest& forest, std::span<const std::uint32_t> trees, const dvec3& eye) {
  long long sum = 0;
  for (std::uint32_t t : trees)
    sum += forest.model(forest.trees()[t].species).lods[static_cast<size_t>(forest.lodFor(t, eye))].triangleCount();
  return sum;
}

// A scene's terrain, forest and objects, their object-ID renderers and a BVH of one object per
// leaf: what the geometry-query tests cull and compare with brute force.
struct IdScene {
  explicit IdScene(const Scene& scene)
      : terrain(*scene.terrain),
        forest(*scene.vegetation, terrain),
        objects(&terrain, &forest, scene.props),
        terrainIds(terrain, render::TerrainRenderer::Output::ObjectId, objects.terrainIdBase()),
        treeIds(forest, render::TreeRenderer::Output::ObjectId, objects.treeIdBase()),
        bvh(objects.boxes(), 1) {}
  // Brute force: every object drawn into the bound ID target.
  void drawAll(const Camera& camera, const terrain::TerrainLod& lod, const SunSettings& sun) const {
    render::SceneDrawer all(objects, &terrainIds, &treeIds, nullptr, camera, &lod, 0.0, sun);
    culling::OcclusionCuller none;
    none.cull(bvh, objects.boxes(), camera, culling::CullingStrategy::None, all, objects.queryShapes(&lod));
  }
  const terrain::Terrain terrain;
  const vegetation::Forest forest;
  const render::SceneObjects objects;
  const render::TerrainRenderer terrainIds;
  const render::TreeRenderer treeIds;
  const culling::Bvh bvh;
};

// The thesis scene cut down to 16 trees, 16 m apart, on a 64 m tile of gentle terrain.
Scene sixteenThesisTrees() {
  Scene scene = loadScene(std::string(FOREST_REPO_DATA) + "/scenes/thesis-demo.toml");
  scene.terrain->size = 64.0;
  scene.terrain->samples = 65;
  scene.terrain->height_max = 1.0;
  scene.terrain->feature_size = 40.0;
  scene.vegetation->grid = 4;
  return scene;
}

// Wraps a drawer: counts how often each object is drawn and the primitives the GPU generated for
// the draws (occlusion-query boxes are drawn outside them and not counted).
struct CountingDrawer : culling::ObjectDrawer {
  culling::ObjectDrawer& inner;
  std::vector<int> timesDrawn;
  long long primitives = 0;
  gl::Query query{GL_PRIMITIVES_GENERATED};
  CountingDrawer(culling::ObjectDrawer& drawer, std::size_t objects) : inner(drawer), timesDrawn(objects, 0) {}
  long long draw(std::span<const std::uint32_t> objects) override {
    for (std::uint32_t o : objects) ++timesDrawn[o];
    glBeginQuery(GL_PRIMITIVES_GENERATED, query.id());
    const long long triangles = inner.draw(objects);
    glEndQuery(GL_PRIMITIVES_GENERATED);
    GLuint64 generated = 0;
    glGetQueryObjectui64v(query.id(), GL_QUERY_RESULT, &generated);
    primitives += static_cast<long long>(generated);
    return triangles;
  }
  bool queriesOwnGeometry(std::uint32_t object, culling::QueryGeometry geometry) const override {
    return inner.queriesOwnGeometry(object, geometry);
  }
  long long drawGeometryQueries(std::span<const std::uint32_t> objects, std::span<const std::uint32_t> slots,
                                culling::QueryGeometry geometry) override {
    for (std::uint32_t o : objects) ++(geometry == culling::QueryGeometry::Exact ? exactQueries : hullQueries)[o];
    return inner.drawGeometryQueries(objects, slots, geometry);
  }
  std::map<std::uint32_t, int> exactQueries, hullQueries;  // per object: geometry queries drawn
};

// The batched draw: a list of trees of both species at every LOD becomes as many instances as
// trees, each once — the GPU generates exactly the listed trees' mesh triangles, and the ID image
// shows listed trees only.
TEST_F(TreeVisibilityGl, TheBatchedDrawDrawsEachListedTreeOnce) {
  const Scene scene = loadScene(std::string(FOREST_REPO_DATA) + "/scenes/forest.toml");
  const terrain::Terrain terrain(*scene.terrain);
  const vegetation::Forest forest(*scene.vegetation, terrain);
  const render::TreeRenderer trees(forest, render::TreeRenderer::Output::ObjectId, 1);
  Camera camera = scene.startCamera();
  camera.aspect = static_cast<double>(kWidth) / kHeight;
  camera.position.y = terrain.heightAt(camera.position.x, camera.position.z) + 30.0;
  camera.pitch = glm::radians(-15.0);
  const std::vector<std::uint32_t> inView = trees.treesInFrustum(camera);
  std::vector<std::uint32_t> listed;  // every third tree in view
  for (size_t k = 0; k < inView.size(); k += 3) listed.push_back(inView[k]);
  ASSERT_GT(listed.size(), 50u);
  std::set<int> lods;
  for (std::uint32_t t : listed) lods.insert(forest.lodFor(t, camera.position));
  EXPECT_GE(lods.size(), 2u) << "the list should span LODs";

  const IdDepthTarget target(kWidth, kHeight);
  target.bindAndClear();
  gl::Query generated(GL_PRIMITIVES_GENERATED);
  glBeginQuery(GL_PRIMITIVES_GENERATED, generated.id());
  const render::TreeRenderer::Stats stats = trees.draw(camera, listed, 0.0, scene.sun);
  glEndQuery(GL_PRIMITIVES_GENERATED);
  GLuint64 primitives = 0;
  glGetQueryObjectui64v(generated.id(), GL_QUERY_RESULT, &primitives);
  EXPECT_EQ(static_cast<long long>(primitives), meshTriangles(forest, listed, camera.position));
  EXPECT_EQ(stats.trees, static_cast<int>(listed.size()));
  EXPECT_LE(stats.draws, vegetation::kSpeciesCount * vegetation::kTreeLods);

  const std::set<std::uint32_t> listedSet(listed.begin(), listed.end());
  std::set<std::uint32_t> seen;
  for (std::uint32_t id : target.readIds())
    if (id != 0) seen.insert(id - 1);
  EXPECT_GT(seen.size(), listed.size() / 4);
  for (std::uint32_t t : seen) EXPECT_TRUE(listedSet.count(t)) << "tree " << t << " has pixels but was not listed";
}

// One cluster of 16 trees (what culling decided for before: one object), seen through a narrow
// view that holds one of them. Culling per tree draws that tree's triangles only, from the second
// frame on (CHC++ has no history on the first); the whole cluster would be 16 trees' triangles.
TEST_F(TreeVisibilityGl, OneVisibleTreeOfAClusterDrawsThatTreeOnly) {
  const Scene scene = sixteenThesisTrees();
  const terrain::Terrain terrain(*scene.terrain);
  const vegetation::Forest forest(*scene.vegetation, terrain);
  ASSERT_EQ(forest.trees().size(), 16u);
  ASSERT_EQ(forest.clusters().size(), 1u);
  const render::SceneObjects objects(&terrain, &forest, scene.props);
  const render::TreeRenderer treeIds(forest, render::TreeRenderer::Output::ObjectId, objects.treeIdBase());
  const culling::Bvh bvh(objects.boxes(), scene.culling.leaf_size);

  // The eye 12 m above and 8 m beside the tree nearest the centre, looking at its box through a
  // 10° field of view.
  std::uint32_t target = 0;
  for (std::uint32_t t = 1; t < forest.trees().size(); ++t)
    if (glm::length(forest.trees()[t].position) < glm::length(forest.trees()[target].position)) target = t;
  const dvec3 centre = forest.treeBounds(target).centre();
  Camera camera;
  camera.position = centre + dvec3(0.0, 12.0, 8.0);
  camera.aspect = static_cast<double>(kWidth) / kHeight;
  camera.fovy = glm::radians(10.0);
  camera.near = 0.1;
  camera.far = 100.0;
  const dvec3 to = centre - camera.position;
  camera.yaw = std::atan2(-to.x, -to.z);
  camera.pitch = std::asin(to.y / glm::length(to));

  const IdDepthTarget image(kWidth, kHeight);
  culling::OcclusionCuller culler;
  for (int frame = 0; frame < 4; ++frame) {
    image.bindAndClear();
    render::SceneDrawer drawer(objects, nullptr, &treeIds, nullptr, camera, nullptr, 0.0, SunSettings{});  // trees only
    CountingDrawer counting(drawer, objects.boxes().size());
    const culling::CullingResult& r = culler.cull(bvh, objects.boxes(), camera, culling::CullingStrategy::ChcPlusPlus, counting, objects.queryShapes(nullptr));
    std::set<std::uint32_t> treesInImage;
    for (std::uint32_t id : image.readIds())
      if (id >= objects.treeIdBase() && id < objects.propIdBase()) treesInImage.insert(id - objects.treeIdBase());
    ASSERT_EQ(treesInImage, std::set<std::uint32_t>{target}) << "frame " << frame << ": the view should show one tree";
    for (int times : counting.timesDrawn) EXPECT_LE(times, 1) << "frame " << frame;
    if (frame == 0) continue;
    const std::uint32_t one[] = {target};
    EXPECT_EQ(counting.primitives, meshTriangles(forest, one, camera.position)) << "frame " << frame;
    EXPECT_EQ(r.stats.trianglesDrawn, counting.primitives) << "frame " << frame;
    EXPECT_TRUE(std::binary_search(r.visibleObjects.begin(), r.visibleObjects.end(),
                                   static_cast<std::uint32_t>(objects.tileCount()) + target));
  }
}

// A tree whose box holds the eye but none of whose triangles is in view: the eye stands in a
// corner of its box, 1 m above the ground, looking away from it. CHC++ §3.6 takes a leaf whose box
// holds the eye (or meets the near rectangle) as visible without a query — its box's faces, or a
// hull's, are cut by the near plane and would miss fragments — so such a tree was drawn every
// frame. Its own triangles are clipped there exactly as its draw is: asked with them
// (QueryGeometry::Exact), it is not drawn at all, and the image still equals brute force's.
TEST_F(TreeVisibilityGl, ATreeWhoseBoxHoldsTheEyeIsDrawnOnlyWhenItsTrianglesShow) {
  const Scene scene = sixteenThesisTrees();
  ASSERT_TRUE(scene.culling.geometry_queries);
  ASSERT_EQ(scene.culling.leaf_size, 1);  // IdScene's
  const IdScene built(scene);
  [[maybe_unused]] const auto& [terrain, forest, objects, terrainIds, treeIds, bvh] = built;

  // The tree nearest the centre; the eye 1 m above the ground in the corner of its box (outside
  // the cone, whose footprint is the circle inscribed in the box), looking out of the corner.
  std::uint32_t target = 0;
  for (std::uint32_t t = 1; t < forest.trees().size(); ++t)
    if (glm::length(forest.trees()[t].position) < glm::length(forest.trees()[target].position)) target = t;
  const std::uint32_t targetObject = static_cast<std::uint32_t>(objects.tileCount()) + target;
  const Aabb box = objects.boxes()[targetObject];
  Camera camera = scene.startCamera();
  camera.aspect = static_cast<double>(kWidth) / kHeight;
  const double inset = 0.15 * (box.max.x - box.min.x);  // well beyond the near plane's 0.1 m
  camera.position = dvec3(box.min.x + inset, 0.0, box.min.z + inset);
  camera.position.y = terrain.heightAt(camera.position.x, camera.position.z) + 1.0;
  ASSERT_TRUE(box.contains(camera.position)) << "the eye should stand in the tree's box";
  camera.yaw = std::atan2(1.0, 1.0);  // along (−1, 0, −1): out of the box's corner
  camera.pitch = 0.0;
  ASSERT_TRUE(Frustum(camera).mayIntersect(box)) << "the box should reach into the view";
  const terrain::TerrainLod lod = terrain.lodFor(camera, kHeight);

  const IdDepthTarget image(kWidth, kHeight);
  image.bindAndClear();
  built.drawAll(camera, lod, scene.sun);
  const std::vector<std::uint32_t> bruteIds = image.readIds();
  const std::vector<float> bruteDepth = image.readDepth();
  ASSERT_EQ(std::count(bruteIds.begin(), bruteIds.end(), objects.treeIdBase() + target), 0) << "the tree should have no pixel";

  culling::OcclusionCuller culler;
  culler.setParameters(scene.culling);
  for (int frame = 0; frame < scene.culling.visible_requery_frames + 2; ++frame) {
    image.bindAndClear();
    render::SceneDrawer drawer(objects, &terrainIds, &treeIds, nullptr, camera, &lod, 0.0, scene.sun);
    CountingDrawer counting(drawer, objects.boxes().size());
    const culling::CullingResult& r =
        culler.cull(bvh, objects.boxes(), camera, culling::CullingStrategy::ChcPlusPlus, counting, objects.queryShapes(&lod));
    EXPECT_EQ(image.readIds(), bruteIds) << "frame " << frame;
    EXPECT_EQ(image.readDepth(), bruteDepth) << "frame " << frame;
    EXPECT_EQ(counting.timesDrawn[targetObject], 0) << "frame " << frame;
    EXPECT_FALSE(std::binary_search(r.visibleObjects.begin(), r.visibleObjects.end(), targetObject)) << "frame " << frame;
    EXPECT_GE(counting.exactQueries[targetObject], 1) << "frame " << frame << ": asked with its own triangles";
    EXPECT_EQ(counting.hullQueries[targetObject], 0) << "frame " << frame << ": never with its hull";
  }
}

// Geometry queries ([culling] geometry_queries): a box sees through the gaps between nearer crowns,
// and a tile's block boxes over the crest of the hill in front of it; a tree's or a tile's own
// triangles do not. On a still ground-level view into the default forest, every visible leaf is
// queried again with its triangles within n_av frames (§3.3), against the depth of everything
// visible the frame before; so after n_av + 2 frames chc++ draws exactly the trees and the terrain
// tiles that have a pixel in the brute-force object-ID image — no more (and, as always, no fewer).
// Box queries alone draw more trees and more tiles on this view (checked too, so that the view can
// tell them apart). Results read deterministically and as soon as available (async) alike.
TEST_F(TreeVisibilityGl, GeometryQueriesDrawExactlyTheTreesAndTilesWithPixelsOnAStillView) {
  const Scene scene = loadScene(std::string(FOREST_REPO_DATA) + "/scenes/forest.toml");
  const IdScene built(scene);
  [[maybe_unused]] const auto& [terrain, forest, objects, terrainIds, treeIds, bvh] = built;
  Camera camera = scene.startCamera();
  camera.aspect = static_cast<double>(kWidth) / kHeight;
  const terrain::TerrainLod lod = terrain.lodFor(camera, kHeight);
  const IdDepthTarget image(kWidth, kHeight);
  auto treesIn = [&](std::span<const std::uint32_t> ids) {
    std::set<std::uint32_t> trees;
    for (std::uint32_t id : ids)
      if (id >= objects.treeIdBase() && id < objects.propIdBase()) trees.insert(id - objects.treeIdBase());
    return trees;
  };
  auto tilesIn = [&](std::span<const std::uint32_t> ids) {
    std::set<std::uint32_t> tiles;
    for (std::uint32_t id : ids)
      if (id >= objects.terrainIdBase() && id < objects.treeIdBase()) tiles.insert(id - objects.terrainIdBase());
    return tiles;
  };
  // Brute force: every object drawn, the trees with a pixel.
  image.bindAndClear();
  built.drawAll(camera, lod, scene.sun);
  const std::set<std::uint32_t> withPixels = treesIn(image.readIds());
  const std::set<std::uint32_t> tilesWithPixels = tilesIn(image.readIds());
  ASSERT_GT(withPixels.size(), 100u) << "the view should look into the forest";

  struct Run {
    bool geometryQueries;
    culling::QueryMode mode;
  };
  for (const Run run : {Run{true, culling::QueryMode::Deterministic}, Run{true, culling::QueryMode::Async},
                        Run{false, culling::QueryMode::Deterministic}}) {
    const bool geometryQueries = run.geometryQueries;
    SCOPED_TRACE(std::string(geometryQueries ? "geometry" : "box") + " queries, " + std::string(culling::kQueryModeNames.name(run.mode)));
    CullingSettings settings = scene.culling;
    settings.geometry_queries = geometryQueries;
    culling::OcclusionCuller culler;
    culler.setParameters(settings);
    culler.setQueryMode(run.mode);
    const int frames = settings.visible_requery_frames + 2;
    std::set<std::uint32_t> drawn, tilesDrawn;
    int geometryQueriesIssued = 0;
    for (int frame = 0; frame < frames; ++frame) {
      image.bindAndClear();
      render::SceneDrawer drawer(objects, &terrainIds, &treeIds, nullptr, camera, &lod, 0.0, scene.sun);
      const culling::CullingResult& r =
          culler.cull(bvh, objects.boxes(), camera, culling::CullingStrategy::ChcPlusPlus, drawer, objects.queryShapes(&lod));
      EXPECT_EQ(treesIn(image.readIds()), withPixels) << "frame " << frame << ": the image must equal brute force's";
      drawn.clear();
      tilesDrawn.clear();
      for (std::uint32_t o : r.visibleObjects) {
        if (o >= objects.tileCount()) drawn.insert(static_cast<std::uint32_t>(o - objects.tileCount()));
        else tilesDrawn.insert(o);
      }
      geometryQueriesIssued = r.stats.geometryQueries;
    }
    std::printf("[geometry queries %s, %s reads] %zu trees with pixels, %zu drawn; %zu tiles with pixels, %zu drawn\n",
                geometryQueries ? "on" : "off", std::string(culling::kQueryModeNames.name(run.mode)).c_str(), withPixels.size(), drawn.size(),
                tilesWithPixels.size(), tilesDrawn.size());
    if (geometryQueries) {
      EXPECT_GT(geometryQueriesIssued, 0);
      EXPECT_EQ(drawn, withPixels) << drawn.size() << " trees drawn, " << withPixels.size() << " with pixels";
      EXPECT_EQ(tilesDrawn, tilesWithPixels) << tilesDrawn.size() << " tiles drawn, " << tilesWithPixels.size() << " with pixels";
    } else {
      EXPECT_EQ(geometryQueriesIssued, 0);
      EXPECT_GT(drawn.size(), withPixels.size()) << "box queries should see through the crowns' gaps on this view";
      EXPECT_GT(tilesDrawn.size(), tilesWithPixels.size()) << "block boxes should see over the hills' crests on this view";
    }
  }
}

// A scene drawer that adds up what its geometry queries should draw, from the queried objects
// alone: a thesis tree's query hull, 90 triangles, or where the query must be exact (a tree beside
// the eye) the mesh of the tree's LOD; a terrain tile, its level's grid (the level the LOD gives
// the tile, terrain::tileGridIndices).
struct QueryTallyDrawer : render::SceneDrawer {
  QueryTallyDrawer(const render::SceneObjects& objects, const vegetation::Forest& forest, const render::TerrainRenderer* terrainRenderer,
                   const render::TreeRenderer* treeRenderer, const Camera& camera, const terrain::TerrainLod& lod, const SunSettings& sun)
      : SceneDrawer(objects, terrainRenderer, treeRenderer, nullptr, camera, &lod, 0.0, sun),
        sceneObjects(objects),
        trees(forest),
        eye(camera.position),
        eyeLod(lod) {}
  long long drawGeometryQueries(std::span<const std::uint32_t> objects, std::span<const std::uint32_t> slots,
                                culling::QueryGeometry geometry) override {
    for (std::uint32_t o : objects) {
      if (o < sceneObjects.tileCount()) {
        ++tiles;
        triangles += static_cast<long long>(terrain::tileGridIndices(sceneObjects.terrain()->tileLevel(static_cast<int>(o), eyeLod)).size() / 3);
      } else if (geometry == culling::QueryGeometry::HullOrOwn) {
        ++treeQueries;
        triangles += 90;
      } else {
        ++treeQueries;
        ++exactTreeQueries;
        triangles += meshTriangles(trees, {&sceneObjects.objects()[o].index, 1}, eye);
      }
    }
    return SceneDrawer::drawGeometryQueries(objects, slots, geometry);
  }
  const render::SceneObjects& sceneObjects;
  const vegetation::Forest& trees;
  dvec3 eye;
  const terrain::TerrainLod& eyeLod;
  long long treeQueries = 0, exactTreeQueries = 0, tiles = 0, triangles = 0;
};

// Geometry queries with the thesis trees' query hulls (vegetation::SpeciesModel::queryHull, 90
// triangles for the tree's 640): along the thesis walk (data/paths/thesis-walk.toml, every third
// frame of its first 120 at 30 fps, 5184 trees), chc++ with hull queries draws the same depth and
// object IDs as drawing everything, deterministic and async reads alike; each of its geometry
// queries draws one hull (90 triangles a query of a leaf of one tree) or one tile's triangles at its
// level; and it draws fewer trees than chc++ with box queries, which see past the cones through the
// gaps between nearer ones.
TEST_F(TreeVisibilityGl, HullQueriesKeepTheThesisWalkExactAndDrawFewerTreesThanBoxes) {
  Scene scene = loadScene(std::string(FOREST_REPO_DATA) + "/scenes/thesis-demo.toml");
  scene.vegetation->grid = 72;
  const CameraPath path = CameraPath::load(std::string(FOREST_REPO_DATA) + "/paths/thesis-walk.toml");
  const IdScene built(scene);
  [[maybe_unused]] const auto& [terrain, forest, objects, terrainIds, treeIds, bvh] = built;
  const IdDepthTarget target(kWidth, kHeight);
  struct Run {
    bool hulls;
    culling::QueryMode mode;
    culling::OcclusionCuller culler{};
    long long treesDrawn = 0;
  };
  std::vector<Run> runs;
  runs.push_back({true, culling::QueryMode::Deterministic});
  runs.push_back({true, culling::QueryMode::Async});
  runs.push_back({false, culling::QueryMode::Deterministic});
  for (Run& run : runs) {
    CullingSettings settings = scene.culling;
    settings.geometry_queries = run.hulls;
    run.culler.setParameters(settings);
    run.culler.setQueryMode(run.mode);
  }
  long long geometryQueries = 0, exactQueries = 0, tileQueries = 0;
  int views = 0;
  for (int f = 0; f < 120; f += 3, ++views) {
    const CameraPose pose = path.at(path.startTime() + f / 30.0);
    Camera camera = scene.startCamera();
    camera.aspect = static_cast<double>(kWidth) / kHeight;
    camera.position = pose.position + dvec3(0.0, terrain.heightAt(pose.position.x, pose.position.z), 0.0);
    camera.yaw = glm::radians(pose.yaw_deg);
    const terrain::TerrainLod lod = terrain.lodFor(camera, kHeight);
    target.bindAndClear();
    built.drawAll(camera, lod, scene.sun);
    const std::vector<std::uint32_t> bruteIds = target.readIds();
    const std::vector<float> bruteDepth = target.readDepth();
    for (Run& run : runs) {
      SCOPED_TRACE(std::string(run.hulls ? "hull" : "box") + " queries, " + std::string(culling::kQueryModeNames.name(run.mode)) +
                   ", frame " + std::to_string(f));
      target.bindAndClear();
      QueryTallyDrawer drawer(objects, forest, &terrainIds, &treeIds, camera, lod, scene.sun);
      const culling::CullingResult& r =
          run.culler.cull(bvh, objects.boxes(), camera, culling::CullingStrategy::ChcPlusPlus, drawer, objects.queryShapes(&lod));
      EXPECT_EQ(target.readIds(), bruteIds);
      EXPECT_EQ(target.readDepth(), bruteDepth);
      EXPECT_EQ(r.stats.geometryQueries, drawer.treeQueries + drawer.tiles);  // leaves of one object each
      EXPECT_EQ(r.stats.queryTriangles, drawer.triangles);
      if (run.hulls && run.mode == culling::QueryMode::Deterministic) {
        geometryQueries += drawer.treeQueries;
        exactQueries += drawer.exactTreeQueries;
        tileQueries += drawer.tiles;
      }
      for (std::uint32_t o : r.visibleObjects) run.treesDrawn += o >= objects.tileCount() ? 1 : 0;
    }
  }
  std::printf("[hull queries] %d views of the thesis walk: %lld tree (%lld of them exact, beside the eye) and %lld tile geometry "
              "queries; trees drawn %lld with hulls, %lld with boxes\n", views, geometryQueries, exactQueries, tileQueries,
              runs[0].treesDrawn, runs[2].treesDrawn);
  EXPECT_GT(geometryQueries, 0);
  EXPECT_GT(tileQueries, 0);
  EXPECT_LT(runs[0].treesDrawn, runs[2].treesDrawn);
}

}  // namespace
}  // namespace forest::test
