// Casters of the visible sun-facing pixels (CasterSelection::ReceiverPixels: the receiver-box
// selection, then the light-space receiver mask of the read-back G-buffer, shadows::ReceiverMask):
// along 30 views of the default forest, suns from 10° to 80°, one map or three slices, every method
// and PCF radius, the shadow term equals the term with all casters pixel for pixel — with the
// casters drawn only into the texels the pixels' lookups read — and the mask keeps fewer casters
// than the receiver boxes. The same for the mask built and tested on the GPU
// (CasterSelection::ReceiverMaskGpu), PCF 0 to 4, with the trees hidden from the light by those
// that counted in a frame before at the view culled. With BVH leaves of 16, only the objects with
// pixels select casters.
#include <cmath>
#include <cstdio>
#include <set>
#include <vector>

#include "forest/core/scene.hpp"
#include "forest/render/frame.hpp"
#include "gl_test_support.hpp"
#include "test_paths.hpp"

namespace forest::test {
namespace {

using glm::dvec3;

constexpr int kWidth = 320, kHeight = 240;

class ReceiverPixelsGl : public GlTest {};

// The default forest, a frame of it (which reads scene.sun at every frame) and its start camera.
struct ForestSweep {
  Scene scene = loadScene(std::string(FOREST_REPO_DATA) + "/scenes/forest.toml");
  render::Frame frame{scene, kWidth, kHeight};
  Camera camera = frame.startCamera();
  ForestSweep() { camera.aspect = static_cast<double>(kWidth) / kHeight; }
  // Moves to view v of the sweep (stepForestView) with the sun at elevation 10° to 80° in five
  // steps and azimuth `azimuthDeg` + v · `stepDeg`.
  void view(int v, double azimuthDeg, double stepDeg) {
    stepForestView(camera, *frame.terrain(), v);
    const double e = glm::radians(10.0 + 70.0 * (v % 5) / 4.0), a = glm::radians(azimuthDeg + stepDeg * v);
    scene.sun.direction = -dvec3(std::cos(e) * std::cos(a), std::sin(e), std::cos(e) * std::sin(a));
  }
};

TEST_F(ReceiverPixelsGl, CastersOfTheSunFacingPixelsGiveTheTermOfAllCasters) {
  if (backendUnderTest() != "egl") GTEST_SKIP() << "the engine's own logic: checked on the egl backend";
  ForestSweep sweep;
  render::Frame& frame = sweep.frame;
  const Camera& camera = sweep.camera;
  const shadows::ShadowMethod methods[] = {shadows::ShadowMethod::Uniform, shadows::ShadowMethod::UniformStable,
                                           shadows::ShadowMethod::Lispsm, shadows::ShadowMethod::Tsm};
  int views = 0, fewer = 0;
  long long maskCasters = 0, boxCasters = 0;
  for (int v = 0; v < 30; ++v) {
    sweep.view(v, 25.0, 47.0);
    if (v % kSweepStride != 0) continue;
    render::FrameSettings settings;
    settings.method = methods[v % 4];
    settings.shadowMapSize = 1024;
    settings.pcfRadius = v % 3;
    settings.cascades = v % 2 == 0 ? 1 : 3;
    // The casters drawn only where the pixels' lookups read (ShadowSlice::texelsRead); the rest
    // stays cleared: a texel read but not drawn reads as lit where a caster shadows it.
    settings.wholeShadowMap = false;
    settings.hiddenCasters = render::HiddenCasters::Cull;  // auto would draw them in a grove this small
    // Every other view after a frame at the same view: the trees hidden from the sun culled against
    // a layer that holds the trees that counted in it (CasterOcclusion), else against the terrain.
    const CasterComparison c =
        compareSelectedWithAllCasters(frame, camera, 0.5 * v, settings, render::CasterSelection::ReceiverPixels, (v / kSweepStride) % 2);
    EXPECT_EQ(c.differ, 0) << "view " << v << ": " << c.differ << " pixels";
    const CasterComparison boxes = compareSelectedWithAllCasters(frame, camera, 0.5 * v, settings);
    EXPECT_LE(c.selectedCasters, boxes.selectedCasters) << "view " << v;  // the mask only removes
    fewer += c.selectedCasters < boxes.selectedCasters ? 1 : 0;
    maskCasters += c.selectedCasters;
    boxCasters += boxes.selectedCasters;
    ++views;
  }
  std::printf("[receiver pixels] %d views: %lld casters from the pixels, %lld from the receiver boxes\n", views, maskCasters,
              boxCasters);
  EXPECT_EQ(views, 30 / kSweepStride);
  EXPECT_GT(fewer, 25 / kSweepStride);
}

// With BVH leaves of 16 objects ([culling] leaf_size) chc++ draws whole leaves: its visible set
// holds trees with no pixel. Along a walk of chc++ frames, the objects whose boxes select casters are
// exactly those with an ID in the frame's G-buffer (counted here from the IDs read back), and the
// term with the casters they select is the term of all casters.
TEST_F(ReceiverPixelsGl, OnlyTheObjectsWithPixelsSelectCastersFromBigLeaves) {
  if (backendUnderTest() != "egl") GTEST_SKIP() << "the engine's own logic: checked on the egl backend";
  Scene scene = loadScene(std::string(FOREST_REPO_DATA) + "/scenes/forest.toml");
  scene.culling.leaf_size = 16;
  render::Frame frame{scene, kWidth, kHeight};
  Camera camera = frame.startCamera();
  camera.aspect = static_cast<double>(kWidth) / kHeight;
  render::FrameSettings settings;
  settings.casters = render::CasterSelection::ReceiverPixels;
  settings.queries = culling::QueryMode::Deterministic;
  settings.timing = gl::TimingMode::GpuQueries;  // chc++ every frame: no switch to frustum culling by measured times
  int frames = 0, moreVisible = 0;
  for (int v = 0; v < 24; ++v) {
    stepForestView(camera, *frame.terrain(), v);
    const render::FrameStats stats = frame.render(camera, 0.5 * v, settings);
    std::set<std::uint32_t> withPixels;
    for (std::uint32_t id : frame.readObjectIds())
      if (id != 0) withPixels.insert(id - 1);  // IDs from 1 in object order, 0 the sky
    EXPECT_EQ(stats.casterReceivers, static_cast<int>(withPixels.size())) << "frame " << v;
    moreVisible += stats.visibleObjects > stats.casterReceivers ? 1 : 0;
    ++frames;
  }
  EXPECT_EQ(frames, 24);
  EXPECT_GT(moreVisible, 20) << "the leaves of 16 should bring in trees without pixels";
  for (int v = 0; v < 3; ++v) {
    render::FrameSettings exact;
    exact.pcfRadius = v;
    exact.cascades = v == 1 ? 3 : 1;
    const CasterComparison c = compareSelectedWithAllCasters(frame, camera, 12.0 + v, exact, render::CasterSelection::ReceiverPixels);
    EXPECT_EQ(c.differ, 0) << "view " << v << ": " << c.differ << " pixels";
    stepForestView(camera, *frame.terrain(), v);
  }
}

TEST_F(ReceiverPixelsGl, TreesKeptOnTheGpuGiveTheTermOfAllCasters) {
  if (backendUnderTest() != "egl") GTEST_SKIP() << "the engine's own logic: checked on the egl backend";
  ForestSweep sweep;
  render::Frame& frame = sweep.frame;
  const Camera& camera = sweep.camera;
  const shadows::ShadowMethod methods[] = {shadows::ShadowMethod::Lispsm, shadows::ShadowMethod::Tsm,
                                           shadows::ShadowMethod::Uniform, shadows::ShadowMethod::UniformStable};
  int views = 0, fewer = 0;
  long long gpuCasters = 0, boxCasters = 0;
  for (int v = 0; v < 30; ++v) {
    sweep.view(v, 40.0, 53.0);
    if (v % kSweepStride != 0) continue;
    render::FrameSettings settings;
    settings.method = methods[v % 4];
    // 1000: pyramids whose levels have odd sizes (125 → 62: the last texel folds into the one before).
    settings.shadowMapSize = v % 3 == 2 ? 1000 : 1024;
    settings.pcfRadius = (v / 2) % 5;  // 0 … 4, each with both layouts
    settings.cascades = v % 2 == 0 ? 1 : 3;
    // A frame at the view first, as in a walk: its trees that counted are drawn first in the next,
    // the occluders the others are tested against (GpuCasterFilter).
    render::FrameSettings before = settings;
    before.casters = render::CasterSelection::ReceiverMaskGpu;
    before.culling = culling::CullingStrategy::Frustum;
    frame.render(camera, 0.5 * v, before);
    const CasterComparison c = compareSelectedWithAllCasters(frame, camera, 0.5 * v, settings, render::CasterSelection::ReceiverMaskGpu);
    EXPECT_EQ(c.differ, 0) << "view " << v << ": " << c.differ << " pixels";
    const CasterComparison boxes = compareSelectedWithAllCasters(frame, camera, 0.5 * v, settings);
    EXPECT_LE(c.selectedCasters, boxes.selectedCasters) << "view " << v;  // the GPU only removes
    fewer += c.selectedCasters < boxes.selectedCasters ? 1 : 0;
    gpuCasters += c.selectedCasters;
    boxCasters += boxes.selectedCasters;
    ++views;
  }
  std::printf("[receiver mask on the GPU] %d views: %lld casters kept on the GPU, %lld from the receiver boxes\n", views,
              gpuCasters, boxCasters);
  EXPECT_EQ(views, 30 / kSweepStride);
  EXPECT_GT(fewer, 25 / kSweepStride);
}

}  // namespace
}  // namespace forest::test
