// What the frame records as showing (render/src/image_visibility.hpp; [culling] image_visibility),
// which the next frame's chc++ reads — written by the lighting pass, or, where the frame reads its
// G-buffer back for the receiver mask (CasterSelection::ReceiverPixels), taken from that read on
// the CPU. Either way, along the default forest's walk, the objects marked are exactly the objects
// of the frame's own ID image (Frame::readObjectIds), and the terrain blocks marked — placed by
// each pixel's position — are those of a brute-force block-ID image
// (TerrainRenderer::Output::BlockId), but for blocks next to one with a pixel: a pixel within
// rounding of a block's edge may land in its neighbour, which only decides whether the culler asks
// a block or draws it untested.
#include <algorithm>
#include <bit>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <utility>
#include <vector>

#include "forest/core/frustum.hpp"
#include "forest/core/scene.hpp"
#include "forest/culling/bvh.hpp"
#include "forest/culling/occlusion_culler.hpp"
#include "forest/render/frame.hpp"
#include "forest/render/scene_objects.hpp"
#include "gl_test_support.hpp"
#include "test_paths.hpp"

namespace forest::test {
namespace {

constexpr int kWidth = 320, kHeight = 180;

class ImageVisibilityGl : public GlTest {};

// Half a step of the default walk, turning by `yawDeg`: nearer trees pass in front of farther ones.
void halfWalkStep(Camera& camera, const terrain::Terrain& terrain, double yawDeg) {
  camera.position.x += 1.5;
  camera.position.z -= 2.0;
  camera.position.y = terrain.heightAt(camera.position.x, camera.position.z) + 1.7;
  camera.yaw += glm::radians(yawDeg);
}

// The readers' settings: the record, and so the frame's guesses and visible sets, from the
// read-back (CasterSelection::ReceiverPixels); and the same without culling.
std::pair<render::FrameSettings, render::FrameSettings> readBackAndBruteForce() {
  render::FrameSettings settings;
  settings.casters = render::CasterSelection::ReceiverPixels;
  render::FrameSettings all = settings;
  all.culling = culling::CullingStrategy::None;
  return {settings, all};
}

// Blocks a and b of one tile's 4 × 4 touch (share an edge or a corner).
bool touching(int a, int b) { return std::abs(a % 4 - b % 4) <= 1 && std::abs(a / 4 - b / 4) <= 1; }

class ImageVisibilityByRecord : public ImageVisibilityGl, public ::testing::WithParamInterface<render::CasterSelection> {};

TEST_P(ImageVisibilityByRecord, MarksExactlyTheObjectsAndBlocksWithPixels) {
  render::FrameSettings settings;
  settings.casters = GetParam();  // ReceiverPixels: the record from the read-back; else the lighting pass's
  const Scene scene = loadScene(std::string(FOREST_REPO_DATA) + "/scenes/forest.toml");
  render::Frame frame(scene, kWidth, kHeight);
  const terrain::Terrain& terrain = *frame.terrain();
  const render::SceneObjects& objects = frame.objects();
  // The brute-force block-ID image: every object with its ID, every tile by its blocks, each
  // block with an ID of its own past the objects' (as bench culling's oracle).
  const auto blockIdBase = static_cast<std::uint32_t>(objects.objects().size() + 1);
  const render::TerrainRenderer blockIds(terrain, render::TerrainRenderer::Output::BlockId, blockIdBase);
  const render::TreeRenderer treeIds(*frame.forest(), render::TreeRenderer::Output::ObjectId, objects.treeIdBase());
  const render::PropRenderer propIds(scene.props, render::PropRenderer::Output::ObjectId, objects.propIdBase());
  const culling::Bvh bvh(objects.boxes(), 1);
  const IdDepthTarget target(kWidth, kHeight);
  constexpr int kBlocks = terrain::Terrain::kMaxBlockBoxes;

  Camera camera = frame.startCamera();
  camera.aspect = static_cast<double>(kWidth) / kHeight;
  int objectsMarked = 0, blocksMarked = 0, blocksBesideOnly = 0;
  for (int v = 0; v < 12; ++v) {
    stepForestView(camera, terrain, 3 * v);
    frame.render(camera, 0.0, settings);
    const render::Frame::ShownInImage shown = frame.readShownInImage();
    ASSERT_EQ(shown.objects.size(), objects.boxes().size());
    ASSERT_EQ(shown.blocks.size(), static_cast<std::size_t>(terrain.tileCount()));

    std::vector<std::uint8_t> expected(objects.boxes().size(), 0);
    for (std::uint32_t id : frame.readObjectIds())
      if (const std::int64_t o = objects.objectOfId(id); o >= 0) expected[static_cast<std::size_t>(o)] = 1;
    EXPECT_EQ(shown.objects, expected) << "view " << v;
    for (std::uint8_t s : shown.objects) objectsMarked += s;

    target.bindAndClear();
    const terrain::TerrainLod lod = terrain.lodFor(camera, kHeight);
    render::SceneDrawer ids(objects, &blockIds, &treeIds, &propIds, camera, &lod, 0.0, scene.sun);
    const Frustum frustum(camera);
    ids.cullTerrainBlocks(&frustum);  // by blocks, so that each writes its own ID
    culling::OcclusionCuller bruteForce;
    bruteForce.cull(bvh, objects.boxes(), camera, culling::CullingStrategy::None, ids);
    // Per tile, the blocks with a pixel, numbered as the 4 × 4 of levels 0–3 (a coarser level's
    // block covers several).
    std::vector<std::uint16_t> withPixels(static_cast<std::size_t>(terrain.tileCount()), 0);
    for (std::uint32_t id : target.readIds()) {
      if (id < blockIdBase) continue;
      const int tile = static_cast<int>((id - blockIdBase) / kBlocks), block = static_cast<int>((id - blockIdBase) % kBlocks);
      withPixels[static_cast<std::size_t>(tile)] |= render::TerrainBlockVisibility::mapLevel(
          static_cast<std::uint16_t>(1u << block), terrain.tileLevel(tile, lod), 0, render::TerrainBlockVisibility::Combine::Any);
    }
    for (int t = 0; t < terrain.tileCount(); ++t) {
      const std::uint16_t marked = shown.blocks[static_cast<std::size_t>(t)], truth = withPixels[static_cast<std::size_t>(t)];
      EXPECT_EQ(marked != 0, truth != 0) << "view " << v << ", tile " << t << ": a tile with pixels marks a block";
      for (int b = 0; b < kBlocks; ++b) {
        if ((marked >> b & 1u) == 0 || (truth >> b & 1u) != 0) continue;
        bool beside = false;
        for (int c = 0; c < kBlocks; ++c) beside = beside || ((truth >> c & 1u) != 0 && touching(b, c));
        EXPECT_TRUE(beside) << "view " << v << ", tile " << t << ": block " << b << " marked, no pixel in it or beside it";
        ++blocksBesideOnly;
      }
      blocksMarked += std::popcount(marked);
    }
  }
  std::printf("[image visibility, casters %s] %d objects and %d blocks marked over 12 views, %d blocks only beside a block with pixels\n",
              std::string(render::kCasterSelectionNames.name(GetParam())).c_str(), objectsMarked, blocksMarked, blocksBesideOnly);
  EXPECT_GT(objectsMarked, 12 * 50);
  EXPECT_GT(blocksMarked, 12 * 4);
}

// [culling] image_reprojection: the trees and props guessed hidden from the last image's samples
// (culling::ReprojectedImage) are asked before they are drawn again; a wrong guess costs a query,
// never a pixel. Along the walk the frame's object IDs equal those of a frame without culling.
TEST_F(ImageVisibilityGl, GuessesFromTheLastImageKeepTheFrameExact) {
  Scene scene = loadScene(std::string(FOREST_REPO_DATA) + "/scenes/forest.toml");
  scene.culling.image_reprojection = true;
  render::Frame guessing(scene, kWidth, kHeight), bruteForce(scene, kWidth, kHeight);
  const auto [settings, all] = readBackAndBruteForce();  // the samples come from the read-back
  Camera camera = guessing.startCamera();
  camera.aspect = static_cast<double>(kWidth) / kHeight;
  int guessed = 0;
  for (int v = 0; v < 12; ++v) {
    halfWalkStep(camera, *guessing.terrain(), 3.0);
    guessed += guessing.render(camera, 0.0, settings).hiddenByReprojection;
    bruteForce.render(camera, 0.0, all);
    const std::vector<std::uint32_t> ids = guessing.readObjectIds(), expected = bruteForce.readObjectIds();
    ASSERT_EQ(ids.size(), expected.size());
    std::size_t differ = 0;
    for (std::size_t i = 0; i < ids.size(); ++i) differ += ids[i] != expected[i] ? 1 : 0;
    EXPECT_EQ(differ, 0u) << "view " << v;
  }
  std::printf("[image reprojection] %d trees and props guessed hidden over 12 views\n", guessed);
  EXPECT_GT(guessed, 0);  // the premise: the guesses were made
}

// [culling] query_payoff (culling::QueryPayoff): the frame probes frustum culling in frames 10 and
// 11 whatever the times say (its first probe), and a frame drawn so takes its visible set from
// the read-back's IDs: exactly the objects with pixels, and z_f from their boxes. Every frame's
// object IDs equal those of a frame without culling; with query_payoff off, chc++ draws them all.
TEST_F(ImageVisibilityGl, FramesDrawnByFrustumCullingTakeTheirVisibleSetFromTheImage) {
  Scene scene = loadScene(std::string(FOREST_REPO_DATA) + "/scenes/forest.toml");
  Scene without = scene;
  without.culling.query_payoff = false;
  ASSERT_TRUE(scene.culling.query_payoff) << "on by default";
  render::Frame paying(scene, kWidth, kHeight), querying(without, kWidth, kHeight), bruteForce(scene, kWidth, kHeight);
  const auto [settings, all] = readBackAndBruteForce();  // the read-back the visible set comes from
  Camera camera = paying.startCamera();
  camera.aspect = static_cast<double>(kWidth) / kHeight;
  int byFrustum = 0;
  for (int f = 0; f < 14; ++f) {
    halfWalkStep(camera, *paying.terrain(), 1.0);
    const render::FrameStats stats = paying.render(camera, 0.0, settings);
    EXPECT_FALSE(querying.render(camera, 0.0, settings).culledByFrustum) << "frame " << f << ", query_payoff off";
    bruteForce.render(camera, 0.0, all);
    const std::vector<std::uint32_t> ids = paying.readObjectIds(), expected = bruteForce.readObjectIds();
    EXPECT_EQ(ids, expected) << "frame " << f;
    EXPECT_EQ(querying.readObjectIds(), expected) << "frame " << f;
    if (f < 10) {
      EXPECT_FALSE(stats.culledByFrustum) << "frame " << f << ": no probe before frame 10";
    } else if (f < 12) {
      EXPECT_TRUE(stats.culledByFrustum) << "frame " << f << ": the first probe";
    }
    std::set<std::uint32_t> withPixels;
    for (std::uint32_t id : ids)
      if (const std::int64_t o = paying.objects().objectOfId(id); o >= 0) withPixels.insert(static_cast<std::uint32_t>(o));
    const std::set<std::uint32_t> visible(paying.visibleObjects().begin(), paying.visibleObjects().end());
    if (stats.culledByFrustum) {
      ++byFrustum;
      EXPECT_EQ(visible, withPixels) << "frame " << f;
      const std::vector<std::uint32_t> list(withPixels.begin(), withPixels.end());
      EXPECT_EQ(stats.farDepth, culling::farDepthOf(list, paying.objects().boxes(), camera)) << "frame " << f;
    } else {
      EXPECT_TRUE(std::includes(visible.begin(), visible.end(), withPixels.begin(), withPixels.end())) << "frame " << f;
    }
  }
  EXPECT_GE(byFrustum, 2);
}

INSTANTIATE_TEST_SUITE_P(LightingPassAndReadBack, ImageVisibilityByRecord,
                         ::testing::Values(render::CasterSelection::Receivers, render::CasterSelection::ReceiverPixels),
                         [](const ::testing::TestParamInfo<render::CasterSelection>& param) {
                           return param.param == render::CasterSelection::ReceiverPixels ? "FromTheReadBack" : "FromTheLightingPass";
                         });

}  // namespace
}  // namespace forest::test
