// The landscape (data/scenes/landscape.toml) at scale: its 4 km terrain with 60 000 of its trees, at
// its stand density on a 1 km square around its walk ([vegetation] area). Along the walk's end — the
// ridge, the open view over kilometres — and from 100 m over the stands: CHC++'s geometry pass
// (depth and object IDs) equals the same frame's geometry by frustum culling, and the casters found
// down the BVH, with the large receivers kept apart, give the shadow term of all casters pixel for
// pixel, for the receiver boxes, the receiver pixels and the mask on the GPU (after a frame of it).
#include <cmath>
#include <cstdio>
#include <vector>

#include "forest/core/camera_path.hpp"
#include "forest/core/scene.hpp"
#include "forest/render/frame.hpp"
#include "gl_test_support.hpp"
#include "test_paths.hpp"

namespace forest::test {
namespace {

constexpr int kWidth = 320, kHeight = 180;

class LandscapeGl : public GlTest {};

// The landscape's trees on a `side` square around its walk, as many as its density puts there.
Scene landscapeAroundItsWalk(double side) {
  Scene scene = loadScene(std::string(FOREST_REPO_DATA) + "/scenes/landscape.toml");
  const double share = side * side / (scene.terrain->size * scene.terrain->size);
  scene.vegetation->count = static_cast<int>(std::lround(scene.vegetation->count * share));
  scene.vegetation->area = glm::dvec4(-230.0 - side / 2, -70.0 - side / 2, -230.0 + side / 2, -70.0 + side / 2);
  return scene;
}

// The ridge at the walk's end (its last 2 s) and two views 100 m over the stands, 15° down.
std::vector<Camera> ridgeAndStandViews(const render::Frame& frame) {
  const CameraPath walk = CameraPath::load(std::string(FOREST_REPO_DATA) + "/paths/landscape-walk.toml");
  std::vector<Camera> views;
  for (double t = walk.endTime() - 2.0; t <= walk.endTime() + 1e-9; t += 1.0) {
    Camera c = frame.cameraAt(walk.at(t), walk.aboveGround());
    c.aspect = static_cast<double>(kWidth) / kHeight;
    views.push_back(c);
  }
  for (int k = 0; k < 2; ++k) {
    CameraPose pose = walk.at(5.0 + 15.0 * k);
    pose.position.y = 100.0;
    pose.pitch_deg = -15.0;
    Camera c = frame.cameraAt(pose, true);
    c.aspect = static_cast<double>(kWidth) / kHeight;
    views.push_back(c);
  }
  return views;
}

// At each view: chc++'s geometry pass (depth and IDs) equals frustum culling's, and each caster
// selection gives the term of all casters. Returns the tree pixels seen over the views.
int expectCullingAndCastersExact(render::Frame& frame, const std::vector<Camera>& views, const render::FrameSettings& settings) {
  int pixelsOfTrees = 0;
  for (size_t v = 0; v < views.size(); ++v) {
    const double time = 0.5 * static_cast<double>(v);
    frame.render(views[v], time, settings);
    const std::vector<std::uint32_t> ids = frame.readObjectIds();
    const std::vector<float> depth = frame.readDepth();
    frame.renderReferenceGeometry(views[v], time);
    const std::vector<std::uint32_t> referenceIds = frame.readObjectIds();
    const std::vector<float> referenceDepth = frame.readDepth();
    int differ = 0;
    for (size_t i = 0; i < ids.size(); ++i) {
      differ += ids[i] != referenceIds[i] || depth[i] != referenceDepth[i] ? 1 : 0;
      pixelsOfTrees += ids[i] >= frame.objects().treeIdBase() && ids[i] < frame.objects().propIdBase() ? 1 : 0;
    }
    EXPECT_EQ(differ, 0) << "view " << v << ": chc++'s geometry pass against frustum culling's";
    // A frame on the GPU's caster filter first, so that the one compared culls the trees hidden from
    // the sun behind those that counted in it (GpuCasterFilter).
    render::FrameSettings before = settings;
    before.casters = render::CasterSelection::ReceiverMaskGpu;
    frame.render(views[v], time, before);
    for (const render::CasterSelection selection : {render::CasterSelection::Receivers, render::CasterSelection::ReceiverPixels,
                                                    render::CasterSelection::ReceiverMaskGpu}) {
      const CasterComparison c = compareSelectedWithAllCasters(frame, views[v], time, settings, selection);
      EXPECT_EQ(c.differ, 0) << "view " << v << ", selection " << static_cast<int>(selection);
      EXPECT_LT(c.selectedCasters, c.allCasters) << "view " << v;
    }
  }
  return pixelsOfTrees;
}

render::FrameSettings landscapeSettings() {
  render::FrameSettings settings;
  settings.shadowMapSize = 1024;
  settings.culling = culling::CullingStrategy::ChcPlusPlus;
  return settings;
}

TEST_F(LandscapeGl, CulledGeometryAndSelectedCastersAreExactOnTheRidgeAndAboveTheStands) {
  if (backendUnderTest() != "egl") GTEST_SKIP() << "the engine's own logic: checked on the egl backend";
  const Scene scene = landscapeAroundItsWalk(1000.0);
  render::Frame frame(scene, kWidth, kHeight);
  ASSERT_EQ(frame.forest()->trees().size(), 62500u);
  const std::vector<Camera> views = ridgeAndStandViews(frame);
  const int pixelsOfTrees = expectCullingAndCastersExact(frame, views, landscapeSettings());
  EXPECT_GT(pixelsOfTrees, kWidth * kHeight / 10);  // the views do look at the forest
  std::printf("[landscape] %zu views, %d tree pixels\n", views.size(), pixelsOfTrees);
}

// The same with far trees as impostors from 120 m (most trees in view, some cross-fading): an
// impostor draws only inside its tree's query boxes, never nearer than where its line enters them,
// and casts only inside its crown slabs, so culling and the caster selections stay exact with the
// representation drawn. The impostors do draw: the ID images differ from the meshes'.
TEST_F(LandscapeGl, ImpostorsKeepCullingAndCasterSelectionExact) {
  if (backendUnderTest() != "egl") GTEST_SKIP() << "the engine's own logic: checked on the egl backend";
  const Scene scene = landscapeAroundItsWalk(1000.0);
  render::Frame frame(scene, kWidth, kHeight);
  const std::vector<Camera> views = ridgeAndStandViews(frame);
  render::FrameSettings settings = landscapeSettings();
  frame.render(views.front(), 0.0, settings);
  const std::vector<std::uint32_t> meshIds = frame.readObjectIds();
  settings.impostorDistance = 120.0;
  frame.resetHistory();
  const int pixelsOfTrees = expectCullingAndCastersExact(frame, views, settings);
  EXPECT_GT(pixelsOfTrees, kWidth * kHeight / 10);
  frame.render(views.front(), 0.0, settings);
  const std::vector<std::uint32_t> impostorIds = frame.readObjectIds();
  long long changed = 0;
  for (size_t i = 0; i < meshIds.size(); ++i) changed += meshIds[i] != impostorIds[i] ? 1 : 0;
  EXPECT_GT(changed, 100) << "the impostors draw";
  std::printf("[landscape, impostors from 120 m] %zu views, %d tree pixels; %lld pixels of the ridge view differ from the meshes'\n",
              views.size(), pixelsOfTrees, changed);
}

}  // namespace
}  // namespace forest::test
