// Terrain visibility by block (render::TerrainBlockVisibility) on a scene whose answer is known in
// closed form: one flat tile (16 blocks) seen from straight above through a roof of two slabs that
// leaves only the corner block open. Once the blocks are known, CHC++ draws that block's
// triangles and the slabs', nothing more; the image (depth and object IDs) equals brute force
// every frame; when the eye drops under the roof, the blocks held back are found and drawn in
// that very frame; and seen from the side through the opening, the held blocks drawn are exactly
// those with a pixel in brute force's block-ID image (each asked on its own).
#include <set>
#include <vector>

#include "forest/core/error.hpp"
#include "forest/core/frustum.hpp"
#include "forest/core/scene.hpp"
#include "forest/culling/bvh.hpp"
#include "forest/culling/occlusion_culler.hpp"
#include "forest/render/scene_objects.hpp"
#include "forest/render/terrain_block_visibility.hpp"
#include "forest/terrain/block_facing.hpp"
#include "gl_test_support.hpp"

namespace forest::test {
namespace {

using glm::dvec3;

class TerrainBlockVisibilityGl : public GlTest {};

constexpr std::uint32_t kBlockIdBase = 1000;  // block IDs apart from the objects' (1–3)

// One 64-quad tile over [−32, 32]², 1 m a quad, all but flat.
TerrainSettings flatTile() {
  TerrainSettings settings;
  settings.size = 64.0;
  settings.samples = 65;
  settings.height_min = 0.0;
  settings.height_max = 0.05;
  settings.feature_size = 50.0;
  settings.octaves = 2;
  settings.seed = 3;
  return settings;
}

// The roof at 5 m: x ≥ −16 everywhere, and z ≥ −16 for x < −16. Block 0 (x, z < −16) is open.
std::vector<PropBox> roof() {
  return {{dvec3(-16, 5, -40), dvec3(40, 5.2, 40), dvec3(0.5)}, {dvec3(-40, 5, -16), dvec3(-16, 5.2, 40), dvec3(0.5)}};
}

// Straight down onto the tile's centre from `height` m, with a 90° square field of view.
Camera lookingDown(double height) {
  Camera camera;
  camera.position = {0.0, height, 0.0};
  camera.pitch = glm::radians(-89.9);
  camera.fovy = glm::radians(90.0);
  camera.aspect = 1.0;
  camera.near = 0.1;
  camera.far = 200.0;
  return camera;
}

// A terrain and props with their ID renderers and BVH (one object a leaf), and one frame of them
// drawn twice into a side × side target: by brute force (every object whole), then by chc++ with
// terrain by block (`blocks`).
struct BlockScene {
  render::SceneObjects objects;
  render::TerrainRenderer terrainIds;
  render::PropRenderer propIds;
  culling::Bvh bvh;
  IdDepthTarget target;
  BlockScene(const terrain::Terrain& terrain, const std::vector<PropBox>& props, int side)
      : objects(&terrain, nullptr, props),
        terrainIds(terrain, render::TerrainRenderer::Output::ObjectId, objects.terrainIdBase()),
        propIds(props, render::PropRenderer::Output::ObjectId, objects.propIdBase()),
        bvh(objects.boxes(), 1),
        target(side, side) {}
  struct Frame {
    std::vector<std::uint32_t> expectedIds, ids;  // brute force's, chc++'s
    std::vector<float> expectedDepth, depth;
    int waitsInCull = 0, waits = 0;  // chc++'s waits in its cull, and with the late blocks' results
    long long triangles = 0;         // chc++'s, with the late blocks'
  };
  Frame draw(const Camera& camera, const terrain::TerrainLod& lod, culling::OcclusionCuller& culler,
             culling::OcclusionCuller& bruteForce, render::TerrainBlockVisibility& blocks) const {
    Frame out;
    target.bindAndClear();
    render::SceneDrawer all(objects, &terrainIds, nullptr, &propIds, camera, &lod, 0.0, SunSettings{});
    (void)bruteForce.cull(bvh, objects.boxes(), camera, culling::CullingStrategy::None, all);
    out.expectedIds = target.readIds();
    out.expectedDepth = target.readDepth();
    target.bindAndClear();
    const Frustum frustum(camera);
    render::SceneDrawer drawer(objects, &terrainIds, nullptr, &propIds, camera, &lod, 0.0, SunSettings{});
    drawer.cullTerrainBlocks(&frustum, &blocks);
    blocks.beginFrame(drawer);
    const culling::CullingResult& r = culler.cull(bvh, objects.boxes(), camera, culling::CullingStrategy::ChcPlusPlus, drawer,
                                                  objects.queryShapes(&lod), &blocks);
    out.waitsInCull = r.stats.waits;
    out.triangles = r.stats.trianglesDrawn + blocks.drawLate(culler);
    out.waits = r.stats.waits;
    out.ids = target.readIds();
    out.depth = target.readDepth();
    return out;
  }
};

TEST_F(TerrainBlockVisibilityGl, OnlyTheBlockSeenThroughTheRoofIsDrawn) {
  const terrain::Terrain terrain(flatTile());
  ASSERT_EQ(terrain.tileCount(), 1);
  constexpr int kSide = 256;
  const BlockScene scene(terrain, roof(), kSide);
  const render::SceneObjects& objects = scene.objects;
  const IdDepthTarget& target = scene.target;
  const Camera above = lookingDown(60.0);
  const Camera under = lookingDown(3.0);  // under the roof: every block shows
  // Far to the side, low: through the open corner it sees the ground of the corner block and of
  // the block beside it (the roof is 5 m up), and no other block.
  Camera oblique = above;
  oblique.position = {-100.0, 40.0, -24.0};
  oblique.yaw = glm::radians(-90.0);  // along +x
  oblique.pitch = std::atan2(-40.0, 92.0);
  const render::TerrainRenderer blockIds(terrain, render::TerrainRenderer::Output::BlockId, kBlockIdBase);

  culling::OcclusionCuller culler, bruteForce;
  render::TerrainBlockVisibility blocks(terrain, 8);
  // Frames 0–5 from above, then under the roof; at frame 6 everything is forgotten (a camera
  // cut), and frames 6–9 are from above again, then from the side.
  constexpr size_t kUnder = 4, kCut = 6, kOblique = 10;
  const std::vector<Camera> frames = {above, above, above, above, under, under, above, above, above, above, oblique, oblique};
  for (size_t f = 0; f < frames.size(); ++f) {
    const Camera& camera = frames[f];
    if (f == kCut) {
      culler.reset();
      blocks.reset();
    }
    const size_t sinceCut = f < kCut ? f : f - kCut;  // frames from above since the last cut: 0–3
    const terrain::TerrainLod lod = terrain.lodFor(camera, kSide);
    const int level = terrain.tileLevel(0, lod);
    const Frustum frustum(camera);
    const BlockScene::Frame frame = scene.draw(camera, lod, culler, bruteForce, blocks);
    const long long triangles = frame.triangles;
    // The blocks' queries went out with chc++'s last batch: where the cull ended waiting for it
    // (frames 0 and 1: the leaves found visible are asked again at the end of the frame, then the
    // next frame), their results came with it; elsewhere they take at most one wait.
    EXPECT_LE(frame.waits, frame.waitsInCull + 1) << "frame " << f;
    if (sinceCut < 2) {
      EXPECT_EQ(frame.waits, frame.waitsInCull) << "frame " << f;
    }
    EXPECT_EQ(frame.ids, frame.expectedIds) << "frame " << f;
    EXPECT_EQ(frame.depth, frame.expectedDepth) << "frame " << f;

    // Closed forms: a box is 12 triangles, a block 2 per cell at the tile's level.
    const long long perBlock = 2LL * terrain::cellsPerBlock(level);
    int blocksInFrustum = 0;
    for (const Aabb& b : terrain.blockBoxes(0, level)) blocksInFrustum += frustum.mayIntersect(b) ? 1 : 0;
    const int cornerInFrustum = frustum.mayIntersect(terrain.blockBoxes(0, level)[0]) ? 1 : 0;
    ASSERT_EQ(terrain::blocksPerTile(level), 16) << "the roof is laid out for 16 blocks";
    if (sinceCut == 0) {  // nothing known yet: every block in the frustum drawn, and asked
      EXPECT_EQ(triangles, 2 * 12 + blocksInFrustum * perBlock);
    } else if (sinceCut < 4) {  // the corner block alone
      EXPECT_EQ(triangles, 2 * 12 + perBlock) << "frame " << f;
      EXPECT_EQ(blocks.stats().drawnInTraversal, 1) << "frame " << f;
      EXPECT_EQ(blocks.stats().held, blocksInFrustum - 1) << "frame " << f;
      EXPECT_EQ(blocks.stats().drawnAfter, 0) << "frame " << f;
    } else if (f == kOblique) {
      // The blocks with a pixel in brute force's block-ID image: the corner block was visible and
      // is drawn in the traversal; of the blocks held back, those with a pixel are drawn after it,
      // each on its own — not every held block of the tile because one of them shows.
      target.bindAndClear();
      std::vector<terrain::TileBlock> inFrustum;
      for (int b = 0; b < terrain::blocksPerTile(level); ++b)
        if (frustum.mayIntersect(terrain.blockBoxes(0, level)[static_cast<size_t>(b)])) inFrustum.push_back({0, level, b});
      (void)blockIds.drawBlocks(render::DrawView::fromCamera(camera, 0.0, SunSettings{}), lod, inFrustum);
      const std::uint32_t roofObjects[] = {1, 2};
      render::SceneDrawer all(objects, &scene.terrainIds, nullptr, &scene.propIds, camera, &lod, 0.0, SunSettings{});
      (void)all.draw(roofObjects);
      std::set<int> withPixels;
      for (std::uint32_t id : target.readIds())
        if (id >= kBlockIdBase && id < kBlockIdBase + 16) withPixels.insert(static_cast<int>(id - kBlockIdBase));
      ASSERT_TRUE(withPixels.count(0) == 1 && withPixels.size() >= 2) << "the view should see the corner block and another";
      ASSERT_LT(withPixels.size() + 1, inFrustum.size()) << "the view should leave blocks in the frustum hidden";
      EXPECT_EQ(blocks.stats().drawnInTraversal, 1) << "the corner block";
      EXPECT_EQ(blocks.stats().held, static_cast<int>(inFrustum.size()) - 1);
      EXPECT_EQ(blocks.stats().drawnAfter, static_cast<int>(withPixels.size()) - 1);
    } else if (f == kUnder) {  // under the roof: the blocks held back are found and drawn after the traversal
      EXPECT_GT(blocksInFrustum - cornerInFrustum, 0);
      EXPECT_EQ(blocks.stats().drawnAfter, blocksInFrustum - cornerInFrustum);
      EXPECT_EQ(triangles, blocksInFrustum * perBlock);  // the roof is behind the eye
    }
  }
}


// A block that comes into view hides what is behind it from the rest of the frame's queries
// (QueriesAfterTraversal::issueDuring): the roof scene with 16 boxes buried 0.5–1.5 m under the
// ground near the middle of the tile, hidden from above by the roof and from under it by the
// ground. Once the eye drops under the roof, the blocks held back from above are asked with the
// first batch of queries and drawn when its results are in; the buried boxes, asked in later
// batches (they sit deeper in the hierarchy), are then hidden. Brute force's image has no pixel
// of them, so the frame draws exactly the ground blocks in the frustum: 2 triangles a cell, and
// no box's 12.
TEST_F(TerrainBlockVisibilityGl, BlocksComingIntoViewHideWhatIsBehindThemInTheSameFrame) {
  const terrain::Terrain terrain(flatTile());
  std::vector<PropBox> props = roof();
  constexpr int kRoofProps = 2, kBuried = 16;
  for (int i = 0; i < kBuried; ++i) {
    const dvec3 corner(-2.0 + (i % 4), -1.5, -2.0 + (i / 4));
    props.push_back({corner, corner + dvec3(0.5, 1.0, 0.5), dvec3(0.5)});
  }
  constexpr int kSide = 256;
  const BlockScene scene(terrain, props, kSide);
  const render::SceneObjects& objects = scene.objects;
  const Camera above = lookingDown(60.0), under = lookingDown(3.0);
  culling::OcclusionCuller culler, bruteForce;
  render::TerrainBlockVisibility blocks(terrain, 8);
  const std::vector<Camera> frames = {above, above, above, under};
  for (size_t f = 0; f < frames.size(); ++f) {
    const Camera& camera = frames[f];
    const terrain::TerrainLod lod = terrain.lodFor(camera, kSide);
    const int level = terrain.tileLevel(0, lod);
    const Frustum frustum(camera);
    const BlockScene::Frame frame = scene.draw(camera, lod, culler, bruteForce, blocks);
    for (std::uint32_t id : frame.expectedIds)
      ASSERT_FALSE(id >= objects.propIdBase() + kRoofProps && id < objects.propIdBase() + kRoofProps + kBuried)
          << "frame " << f << ": a buried box shows in brute force's image";
    EXPECT_EQ(frame.ids, frame.expectedIds) << "frame " << f;
    EXPECT_EQ(frame.depth, frame.expectedDepth) << "frame " << f;
    if (f + 1 < frames.size()) continue;
    int blocksInFrustum = 0;
    for (const Aabb& b : terrain.blockBoxes(0, level)) blocksInFrustum += frustum.mayIntersect(b) ? 1 : 0;
    const int cornerInFrustum = frustum.mayIntersect(terrain.blockBoxes(0, level)[0]) ? 1 : 0;
    ASSERT_GT(blocksInFrustum - cornerInFrustum, 0);
    EXPECT_EQ(blocks.stats().drawnDuring, blocksInFrustum - cornerInFrustum);
    EXPECT_EQ(blocks.stats().drawnAfter, 0);
    EXPECT_EQ(frame.triangles, blocksInFrustum * 2LL * terrain::cellsPerBlock(level)) << "12 triangles a buried box drawn";
  }
}

// OcclusionCuller::queryAfterCull, the batch the blocks' queries go out in: a box behind a wall
// fails, one in front of it passes, one holding the eye passes without a query; malformed groups
// and a call before any cull are refused.
TEST_F(TerrainBlockVisibilityGl, QueriesAfterTheCullSeeTheFinalDepth) {
  const std::vector<PropBox> wall = {{dvec3(-50, -10, -6), dvec3(50, 30, -5), dvec3(0.5)}};
  const render::SceneObjects objects(nullptr, nullptr, wall);
  const render::PropRenderer propIds(wall, render::PropRenderer::Output::ObjectId, objects.propIdBase());
  const culling::Bvh bvh(objects.boxes(), 1);
  Camera camera;
  camera.aspect = 1.0;
  camera.far = 100.0;
  const IdDepthTarget target(64, 64);
  culling::OcclusionCuller culler;
  const std::vector<Aabb> boxes = {Aabb{dvec3(-1, -1, -12), dvec3(1, 1, -10)},   // behind the wall
                                   Aabb{dvec3(-1, -1, -4), dvec3(1, 1, -3)},     // in front of it
                                   Aabb{dvec3(-1, -1, -1), dvec3(1, 1, 1)}};     // holds the eye
  const std::vector<std::uint32_t> oneEach = {1, 2, 3};
  EXPECT_THROW((void)culler.queryAfterCull(boxes, oneEach), Error);  // no frame culled yet
  target.bindAndClear();
  render::SceneDrawer drawer(objects, nullptr, nullptr, &propIds, camera, nullptr, 0.0, SunSettings{});
  const int queriesBefore = culler.cull(bvh, objects.boxes(), camera, culling::CullingStrategy::Chc, drawer).stats.queriesIssued;
  const std::vector<bool> visible = culler.queryAfterCull(boxes, oneEach);
  EXPECT_EQ(visible, (std::vector<bool>{false, true, true}));
  // Two queries went out (the box holding the eye needs none), and the refinement asks the wall
  // again (one more) and keeps it: all counted in the frame's stats.
  const culling::CullingResult& refined = culler.refineVisibleSet(objects.boxes());
  EXPECT_EQ(refined.visibleObjects, std::vector<std::uint32_t>{0});
  EXPECT_EQ(refined.stats.queriesIssued, queriesBefore + 2 + 1);
  EXPECT_TRUE(culler.queryAfterCull({}, {}).empty());
  const std::vector<std::uint32_t> shrinking = {2, 1, 3}, pastTheEnd = {4};
  EXPECT_THROW((void)culler.queryAfterCull(boxes, shrinking), Error);
  EXPECT_THROW((void)culler.queryAfterCull(boxes, pastTheEnd), Error);
}

}  // namespace
}  // namespace forest::test
