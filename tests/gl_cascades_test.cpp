// Z-partitioned shadows (issue "Z-partitioned shadows", DESIGN §4): per-slice caster selection is
// exact, a box's shadow is right on both sides of every split, each slice's LiSPSM n is eq. 8.13 on
// that slice's z0 and z1 worked out from the scene, the splits start at the depth buffer's nearest
// depth and move over time by the smoothing recurrence.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <vector>

#include <fmt/format.h>

#include "forest/core/error.hpp"
#include "forest/core/scene.hpp"
#include "forest/render/frame.hpp"
#include "forest/shadows/cascades.hpp"
#include "gl_test_support.hpp"
#include "test_paths.hpp"

namespace forest::test {
namespace {

using glm::dvec3;

constexpr int kWidth = 320, kHeight = 240;

class CascadesGl : public GlTest {};

// The eye depth of the nearest drawn pixel, from the depth buffer on the CPU (reversed-Z).
double nearestDepthOf(const render::Frame& frame, const Camera& camera) {
  double nearest = std::numeric_limits<double>::infinity();
  for (float d : frame.readDepth())
    if (d > 0.0f) nearest = std::min(nearest, camera.near * camera.far / (camera.near + d * (camera.far - camera.near)));
  return nearest;
}

// Per slice, the term with the selected casters equals the term with all casters, pixel for pixel,
// along 30 views of the default forest (ground level and 40 m up), K = 2, 3, 4 (K = 1:
// FrameGl.CasterSelectionChangesNoShadowForAnyFilterAlongThirtyViews), PCF radius 0 and 2, four
// methods, with and without a blend band.
TEST_F(CascadesGl, SelectedCastersOfEachSliceGiveTheTermOfAllCasters) {
  if (backendUnderTest() != "egl") GTEST_SKIP() << "checked on the egl backend";
  DefaultForestWalk walk(kWidth, kHeight);
  render::Frame& frame = walk.frame;
  const Camera& camera = walk.camera;
  const shadows::ShadowMethod methods[] = {shadows::ShadowMethod::Uniform, shadows::ShadowMethod::UniformStable,
                                           shadows::ShadowMethod::Lispsm, shadows::ShadowMethod::Tsm};
  int views = 0, fewer = 0;
  for (int v = 0; v < 30; ++v) {
    walk.step(v);
    if (v % kSweepStride != 0) continue;
    for (int k = 2; k <= shadows::kMaxCascades; ++k) {
      render::FrameSettings settings;
      settings.method = methods[(v + k) % 4];
      settings.shadowMapSize = 512;
      settings.cascades = k;
      settings.cascadeBlend = v % 2 == 0 ? 0.1 : 0.0;
      settings.pcfRadius = v % 3 == 0 ? 2 : 0;
      const CasterComparison c = compareSelectedWithAllCasters(frame, camera, 0.5 * v, settings);
      ASSERT_EQ(frame.cascadeCount(), k);
      EXPECT_EQ(c.differ, 0) << "view " << v << ", K " << k << ": " << c.differ << " pixels";
      fewer += c.selectedCasters < c.allCasters ? 1 : 0;
      ++views;
    }
  }
  EXPECT_EQ(views, 90 / kSweepStride);
  EXPECT_GT(fewer, 80 / kSweepStride);  // the selection does leave casters out
}

// Kept slices (--keep-slices on): a view rendered after a walk up to it (6 frames, 0.3 m and 0.3° a
// frame), so that its map is one kept or refitted along the walk; its term with the selected casters
// equals its term with all casters, rendered next at the same view with the same map — a kept map
// changes which texels a caster covers, never whether it counts. One map: each slice selects its
// casters alone, and with several the splits would move between the two renders (they are smoothed
// over frames). Not vacuous: most views keep their map.
TEST_F(CascadesGl, KeptSlicesKeepTheSelectedCastersExact) {
  if (backendUnderTest() != "egl") GTEST_SKIP() << "checked on the egl backend";
  DefaultForestWalk walk(kWidth, kHeight);
  render::Frame& frame = walk.frame;
  const Camera& camera = walk.camera;
  const shadows::ShadowMethod methods[] = {shadows::ShadowMethod::Uniform, shadows::ShadowMethod::Lispsm, shadows::ShadowMethod::Tsm};
  int slices = 0, kept = 0;
  for (int v = 0; v < 30; ++v) {
    walk.step(v);
    if (v % kSweepStride != 0) continue;
    render::FrameSettings settings;
    settings.method = methods[v % 3];
    settings.shadowMapSize = 512;
    settings.cascades = 1;
    settings.pcfRadius = v % 4 == 0 ? 2 : 0;
    settings.keepSlices = true;
    settings.culling = culling::CullingStrategy::Frustum;
    settings.casters = v % 2 == 0 ? render::CasterSelection::ReceiverPixels : render::CasterSelection::Receivers;
    settings.wholeShadowMap = false;  // receiver pixels: only the texels the lookups read, in the kept map
    frame.resetHistory();
    for (int step = 6; step > 0; --step) {
      Camera before = camera;
      before.position -= 0.3 * step * camera.forward();
      before.yaw -= glm::radians(0.3 * step);
      frame.render(before, 0.5 * v, settings);
    }
    const render::FrameStats selected = frame.render(camera, 0.5 * v, settings);
    std::vector<glm::dmat4> matrices;
    for (int slice = 0; slice < frame.cascadeCount(); ++slice) {
      matrices.push_back(frame.shadowSetup(slice).worldToShadowClip);
      ++slices;
      kept += selected.cascade[static_cast<size_t>(slice)].keeping.kept ? 1 : 0;
    }
    const std::vector<float> withSelected = frame.readShadowTerm();
    settings.casters = render::CasterSelection::All;
    const render::FrameStats all = frame.render(camera, 0.5 * v, settings);
    for (int slice = 0; slice < frame.cascadeCount(); ++slice)
      ASSERT_EQ(frame.shadowSetup(slice).worldToShadowClip, matrices[static_cast<size_t>(slice)]) << "view " << v << " slice " << slice;
    EXPECT_LT(selected.casterObjects, all.casterObjects) << "view " << v;
    const std::vector<float> withAll = frame.readShadowTerm();
    int differ = 0;
    for (size_t i = 0; i < withAll.size(); ++i) differ += withSelected[i] != withAll[i] ? 1 : 0;
    EXPECT_EQ(differ, 0) << "view " << v << ", " << shadows::kShadowMethodNames.name(settings.method);
  }
  EXPECT_GT(2 * kept, slices) << kept << " of " << slices << " views kept their map";
}

// Cached slices (--cache-slices on): along a walk (4 frames of 0.3 m and 0.5°, then 4 turning 0.5°
// in place; the trees still: no wind) a layer is reused, has the casters it lacks added or is
// redrawn, and the view's term from those
// layers equals its term with all casters drawn afresh into the same map, rendered next at the same
// view — a layer holds the least depth of what was drawn into it, so what it held before and what
// was added equal one draw of them all. One map, as in the test above. Not vacuous: layers are
// reused and added to.
TEST_F(CascadesGl, CachedSlicesEqualTheirRedraw) {
  if (backendUnderTest() != "egl") GTEST_SKIP() << "checked on the egl backend";
  DefaultForestWalk walk(kWidth, kHeight, 0.0);
  render::Frame& frame = walk.frame;
  const Camera& camera = walk.camera;
  const shadows::ShadowMethod methods[] = {shadows::ShadowMethod::Uniform, shadows::ShadowMethod::Lispsm, shadows::ShadowMethod::Tsm};
  std::map<render::SliceUpdate, int> updates;
  for (int v = 0; v < 30; ++v) {
    walk.step(v);
    if (v % kSweepStride != 0) continue;
    render::FrameSettings settings;
    settings.method = methods[v % 3];
    settings.shadowMapSize = 2048;
    settings.cascades = 1;
    settings.keepSlices = true;
    settings.cacheSlices = true;
    settings.culling = culling::CullingStrategy::Frustum;
    settings.casters = v % 2 == 0 ? render::CasterSelection::ReceiverPixels : render::CasterSelection::Receivers;
    settings.wholeShadowMap = false;  // receiver pixels: a rectangle of the layer
    frame.resetHistory();
    render::FrameStats cached;
    for (int step = 8; step >= 0; --step) {
      Camera before = camera;  // walking, then turning in place (the LODs stay, the casters change)
      before.position -= 0.3 * std::max(step - 4, 0) * camera.forward();
      before.yaw -= glm::radians(0.5 * step);
      cached = frame.render(before, 0.5 * v, settings);
      if (step < 8) ++updates[cached.cascade[0].update];
    }
    const glm::dmat4 matrix = frame.shadowSetup(0).worldToShadowClip;
    const std::vector<float> fromCache = frame.readShadowTerm();
    settings.cacheSlices = false;
    settings.casters = render::CasterSelection::All;
    frame.render(camera, 0.5 * v, settings);
    ASSERT_EQ(frame.shadowSetup(0).worldToShadowClip, matrix) << "view " << v;
    const std::vector<float> redrawn = frame.readShadowTerm();
    int differ = 0;
    for (size_t i = 0; i < redrawn.size(); ++i) differ += fromCache[i] != redrawn[i] ? 1 : 0;
    EXPECT_EQ(differ, 0) << "view " << v << ", " << shadows::kShadowMethodNames.name(settings.method) << ", last frame's layer "
                         << render::kSliceUpdateNames.name(cached.cascade[0].update) << " (" << cached.cascade[0].redraw << ")";
  }
  EXPECT_GT(updates[render::SliceUpdate::Reuse], 0);
  EXPECT_GT(updates[render::SliceUpdate::Add], 0);
}

// A beam over a plane along the view, widening with distance (contiguous boxes, each 15% longer
// than the one before), so its shadow and the lit plane beside it lie at every depth: on both sides
// of every split (hard, and with a blend band) the term agrees with the CPU's ray past the boxes on
// every pixel away from the shadow edges, for each method and K = 2, 3, 4.
struct BeamScene {
  Scene scene;
  std::vector<Aabb> boxes;  // the beam's
  Camera camera;
};
BeamScene beamOverPlane() {
  BeamScene b;
  b.scene.sun.direction = glm::normalize(dvec3(1.0, -1.0, 0.2));  // the shadow falls 6 m beside the beam
  b.scene.props.push_back({dvec3(-60, -1, -170), dvec3(60, 0, 5), dvec3(0.6)});  // the plane (top at y = 0)
  for (double z = 2.0; z < 165.0; z *= 1.15) {
    const double half = 0.035 * z + 0.3;  // the shadow stays ≥ 10 pixels wide
    b.scene.props.push_back({dvec3(-half - 8.0, 6.0, -z * 1.15), dvec3(half - 8.0, 6.5, -z), dvec3(0.8)});
    b.boxes.push_back({b.scene.props.back().min, b.scene.props.back().max});
  }
  b.camera = test::cameraAt({0, 15, 4}, 0.0, -14.0, 400.0, static_cast<double>(kWidth) / kHeight);
  return b;
}

// `method` in k slices of 1024² (the beam's runs).
render::FrameSettings slicedSettings(shadows::ShadowMethod method, int k) {
  render::FrameSettings settings;
  settings.method = method;
  settings.shadowMapSize = 1024;
  settings.cascades = k;
  return settings;
}

TEST_F(CascadesGl, BoxShadowsAreRightOnBothSidesOfEverySplit) {
  if (backendUnderTest() != "egl") GTEST_SKIP() << "the engine's own logic: checked on the egl backend";
  const BeamScene beam = beamOverPlane();
  const Scene& scene = beam.scene;
  const std::vector<Aabb>& boxes = beam.boxes;
  render::Frame frame(scene, kWidth, kHeight);
  const Camera& camera = beam.camera;
  int combination = 0;
  for (shadows::ShadowMethod method : {shadows::ShadowMethod::Uniform, shadows::ShadowMethod::UniformStable,
                                       shadows::ShadowMethod::Lispsm, shadows::ShadowMethod::Tsm})
    for (int k = 2; k <= shadows::kMaxCascades; ++k)
      for (double blend : {0.0, 0.1}) {
        if (combination++ % kSweepStride != 0) continue;
        render::FrameSettings settings = slicedSettings(method, k);
        settings.cascadeBlend = blend;
        frame.resetHistory();
        const render::FrameStats stats = frame.render(camera, 0.0, settings);
        const CpuAgreement a = agreementWithCpuShadow(frame, camera, frame.readShadowTerm(), frame.objects().propIdBase(), boxes,
                                                      -scene.sun.direction);
        const std::string what = fmt::format("{} K {} blend {}", shadows::kShadowMethodNames.name(method), k, blend);
        EXPECT_EQ(a.wrong, 0) << what << ": " << a.wrong << " of " << a.checked << " plane pixels disagree";
        EXPECT_GT(a.checked, 30000) << what;
        // Each split has checked shadowed and lit pixels within 10% of it on both sides.
        for (int i = 1; i < k; ++i) {
          const double split = stats.cascade[static_cast<size_t>(i)].fromM;
          int counts[2][2] = {};  // [side][state]
          for (size_t p = 0; p < a.checkedDepths.size(); ++p) {
            const double d = a.checkedDepths[p];
            if (d > split / 1.1 && d < split * 1.1) ++counts[d >= split ? 1 : 0][a.checkedStates[p]];
          }
          for (int side = 0; side < 2; ++side)
            for (int state = 0; state < 2; ++state)
              EXPECT_GT(counts[side][state], 5) << what << ", split " << i << " at " << split << " m, side " << side << ", state " << state;
        }
      }
}

// Unequal layers (FrameSettings::farSliceScale): the last slice's layer is the square of
// round(scale · 1024) texels at the origin of an array texture as large as the largest layer. On
// the beam scene the term still agrees with the CPU's ray past the boxes on every pixel away from
// the shadow edges (the edge band from each slice's own texels), for a far layer half, 1.5 and twice
// the others' side, K = 2 and 4; each layer reads back at its own size.
TEST_F(CascadesGl, UnequalLayersShadowLikeTheCpuRay) {
  if (backendUnderTest() != "egl") GTEST_SKIP() << "the engine's own logic: checked on the egl backend";
  const BeamScene beam = beamOverPlane();
  render::Frame frame(beam.scene, kWidth, kHeight);
  int combination = 0;  // with a stride (sanitizers): scales, methods and K all still vary
  for (double scale : {0.5, 1.5, 2.0})
    for (shadows::ShadowMethod method : {shadows::ShadowMethod::UniformStable, shadows::ShadowMethod::Lispsm})
      for (int k : {2, 4}) {
        if (combination++ % kSweepStride != 0) continue;
        render::FrameSettings settings = slicedSettings(method, k);
        settings.farSliceScale = scale;
        frame.resetHistory();
        const render::FrameStats stats = frame.render(beam.camera, 0.0, settings);
        const std::string what = fmt::format("{} K {} far scale {}", shadows::kShadowMethodNames.name(method), k, scale);
        for (int i = 0; i < k; ++i) {
          const int side = i + 1 < k ? 1024 : static_cast<int>(std::lround(scale * 1024));
          EXPECT_EQ(stats.cascade[static_cast<size_t>(i)].mapSize, side) << what << ", slice " << i;
          EXPECT_EQ(frame.shadowMapSize(i), side) << what << ", slice " << i;
          EXPECT_EQ(frame.readShadowMap(i).size(), static_cast<size_t>(side) * side) << what << ", slice " << i;
        }
        const CpuAgreement a = agreementWithCpuShadow(frame, beam.camera, frame.readShadowTerm(), frame.objects().propIdBase(),
                                                      beam.boxes, -beam.scene.sun.direction);
        EXPECT_EQ(a.wrong, 0) << what << ": " << a.wrong << " of " << a.checked << " plane pixels disagree";
        EXPECT_GT(a.checked, 30000) << what;
        // The far slice's own pixels were checked, shadowed and lit.
        int far[2] = {};
        for (size_t p = 0; p < a.checkedDepths.size(); ++p)
          if (a.checkedDepths[p] >= stats.cascade[static_cast<size_t>(k - 1)].fromM * 1.1) ++far[a.checkedStates[p]];
        EXPECT_GT(far[0], 20) << what;
        EXPECT_GT(far[1], 20) << what;
      }
}

// Scales outside [0.5, 2], a far layer beyond 8192 texels, and the GPU's caster filter (its masks
// are of one size) are refused before anything is drawn.
TEST_F(CascadesGl, UnequalLayersRefuseWhatTheyCannotDraw) {
  const BeamScene beam = beamOverPlane();
  render::Frame frame(beam.scene, kWidth, kHeight);
  auto refused = [&](int size, double scale, render::CasterSelection casters) {
    render::FrameSettings settings;
    settings.shadowMapSize = size;
    settings.cascades = 2;
    settings.farSliceScale = scale;
    settings.casters = casters;
    try {
      frame.render(beam.camera, 0.0, settings);
    } catch (const InputError&) {
      return true;
    }
    return false;
  };
  const render::CasterSelection boxes = render::CasterSelection::Receivers, gpu = render::CasterSelection::ReceiverMaskGpu;
  EXPECT_TRUE(refused(1024, 0.49, boxes));
  EXPECT_TRUE(refused(1024, 2.01, boxes));
  EXPECT_TRUE(refused(8192, 1.5, boxes));  // 12288 texels
  EXPECT_TRUE(refused(1024, 1.5, gpu));
  EXPECT_FALSE(refused(512, 0.5, boxes));   // 256: the smallest layer
  EXPECT_FALSE(refused(1024, 2.0, boxes));
  EXPECT_FALSE(refused(1024, 1.0, gpu));
}

// A camera level over a plane, the sun straight down (the warp axis is the view): slice i's focus body is the slice
// of the frustum over the plane, so its z0 and z1 are the slice's ends, the first no nearer than
// where the frustum's lower edge meets the plane (h / tan(fovy/2)) and, with slices, than the
// nearest visible depth (ShadowInput::nNear). d = z1 − z0 along the view.
// Each slice's n must be eq. 8.13, d / (√(z1/z0) − 1), on these; the splits are Zhang's eq. (4)
// from the nearest visible depth (the bottom pixel row's ground) to z_f (the plane's far end).
TEST_F(CascadesGl, EachSlicesLispsmNIsEq813OnItsOwnDepthRange) {
  Scene scene;
  scene.sun.direction = dvec3(0.0, -1.0, 0.0);
  const double far = 300.0, h = 3.0;
  scene.props.push_back({dvec3(-400, -1, -far), dvec3(400, 0, 1), dvec3(0.6)});
  render::Frame frame(scene, kWidth, kHeight);
  const Camera camera = test::cameraAt({0, h, 0}, 0.0, 0.0, 1000.0, static_cast<double>(kWidth) / kHeight);
  const double tanHalf = std::tan(0.5 * camera.fovy);
  // The nearest pixel centre on the ground: the bottom row, half a pixel above the frustum's edge.
  const double nearest = h / (tanHalf * (1.0 - 1.0 / kHeight));
  const double lambda = 0.7, blend = 0.1;
  for (int k = 1; k <= shadows::kMaxCascades; ++k) {
    render::FrameSettings settings;
    settings.method = shadows::ShadowMethod::Lispsm;
    settings.culling = culling::CullingStrategy::Frustum;
    settings.cascades = k;
    settings.splitLambda = lambda;
    settings.cascadeBlend = blend;
    frame.resetHistory();
    const render::FrameStats stats = frame.render(camera, 0.0, settings);
    ASSERT_NEAR(stats.farDepth, far, 1e-9);
    if (k > 1) {
      ASSERT_NEAR(stats.nearestDepth, nearest, 1e-4 * nearest);
    }
    for (int i = 0; i < k; ++i) {
      const double t = static_cast<double>(i) / k, t1 = static_cast<double>(i + 1) / k;
      auto split = [&](double s) { return lambda * nearest * std::pow(far / nearest, s) + (1 - lambda) * (nearest + (far - nearest) * s); };
      const double from = i == 0 ? camera.near : split(t), to = i + 1 == k ? far : split(t1);
      const render::CascadeStats& c = stats.cascade[static_cast<size_t>(i)];
      EXPECT_NEAR(c.fromM, from, 1e-3 * from) << "K " << k << " slice " << i;
      EXPECT_NEAR(c.toM, to, 1e-3 * to) << "K " << k << " slice " << i;
      // B's ends: the slice's, reaching past the split by the blend band (shadows::kSliceOverlap
      // below); with slices, the first one's n is taken from the nearest visible depth on.
      const double z0 = std::max(i == 0 ? (k > 1 ? nearest : camera.near) : from * (1 - shadows::kSliceOverlap), h / tanHalf);
      const double z1 = i + 1 == k ? far : std::min(far, to * (1 + blend));
      const double expected = (z1 - z0) / (std::sqrt(z1 / z0) - 1.0);
      EXPECT_NEAR(c.n, expected, 2e-3 * expected) << "K " << k << " slice " << i << ": z0 " << z0 << ", z1 " << z1;
    }
  }
}

// The splits start where the view's content does: z_near is the depth buffer's nearest depth (the
// compute reduction against the CPU's minimum over the read-back depth), taken from the frame
// before; along a walk the inner splits move by the smoothing recurrence — 20% of the way in log
// depth toward eq. (4) on this frame's z_f and the previous frame's nearest depth, both ways — and
// after a cut they are eq. (4) itself.
TEST_F(CascadesGl, SplitsStartAtTheNearestDepthAndMoveAFifthOfTheWayPerFrame) {
  if (backendUnderTest() != "egl") GTEST_SKIP() << "the engine's own logic: checked on the egl backend";
  const Scene scene = loadScene(std::string(FOREST_REPO_DATA) + "/scenes/forest.toml");
  render::Frame frame(scene, kWidth, kHeight);
  Camera camera = frame.startCamera();
  camera.aspect = static_cast<double>(kWidth) / kHeight;
  const terrain::Terrain& t = *frame.terrain();
  render::FrameSettings settings;
  settings.cascades = 4;
  settings.splitLambda = 0.8;
  frame.resetHistory();
  double previousNearest = 0.0;
  shadows::SplitDepths previous;
  int moved = 0, reordered = 0;
  for (int f = 0; f < 40; ++f) {
    if (f == 20) frame.resetHistory();  // a cut
    camera.position.x -= 2.0;
    camera.position.z -= 1.5;
    camera.position.y = t.heightAt(camera.position.x, camera.position.z) + 1.7 + (f % 7 == 3 ? 25.0 : 0.0);  // z_f jumps
    camera.yaw += glm::radians(f % 5 == 0 ? 25.0 : 2.0);
    const render::FrameStats stats = frame.render(camera, 0.0, settings);
    const double nearest = nearestDepthOf(frame, camera);
    const bool cut = f == 0 || f == 20;
    // This frame's z_near: its own depth after a cut, else the frame before's.
    const double zNear = cut ? nearest : previousNearest;
    EXPECT_NEAR(stats.nearestDepth, zNear, 1e-4 * zNear) << "frame " << f;
    const shadows::SplitDepths target = shadows::cascadeSplits(std::max(zNear, camera.near), stats.farDepth, 4, 0.8);
    double before = camera.near;  // the split below, as expected
    for (int i = 1; i < 4; ++i) {
      const size_t s = static_cast<size_t>(i);
      double expected = target[s];
      if (!cut) {
        const double smoothed = std::exp(std::log(previous[s]) + 0.2 * (std::log(target[s]) - std::log(previous[s])));
        // A smoothed split that would leave the range or pass the one below takes eq. (4)'s value.
        if (smoothed > before && smoothed < stats.farDepth) expected = smoothed;
      }
      before = expected;
      const double split = stats.cascade[s].fromM;
      if (i > 1 && !(expected > stats.cascade[s - 1].fromM)) {
        // Out of order after the split below fell back: halfway from that split to z_f, so that
        // no slice is empty (shadow_setup_pass.cpp, splitsFor).
        const double halfway = 0.5 * (stats.cascade[s - 1].fromM + stats.farDepth);
        EXPECT_NEAR(split, halfway, 1e-6 * halfway) << "frame " << f << " split " << i << " (reordered)";
        ++reordered;
        continue;
      }
      EXPECT_NEAR(split, expected, 1e-6 * expected) << "frame " << f << " split " << i;
      moved += !cut && std::abs(target[s] / previous[s] - 1.0) > 0.05 ? 1 : 0;
    }
    EXPECT_NEAR(stats.cascade[3].toM, stats.farDepth, 1e-9);
    for (int i = 0; i < 4; ++i)  // every slice serves some depths
      EXPECT_GT(stats.cascade[static_cast<size_t>(i)].toM, stats.cascade[static_cast<size_t>(i)].fromM) << "frame " << f << " slice " << i;
    previousNearest = nearest;
    previous.cascades = 4;
    for (int i = 0; i < 4; ++i) previous[static_cast<size_t>(i)] = stats.cascade[static_cast<size_t>(i)].fromM;
    previous[4] = stats.farDepth;
  }
  EXPECT_GT(moved, 10);  // the targets did jump: the recurrence was exercised
  // The order's fallback is not reached on this walk (reordered is 0); its closed form is checked
  // on a z_f that falls tenfold in CascadeSplits.ASplitThatWouldPassTheOneBelowGoesHalfwayToTheFarEnd.
  std::printf("splits moved: %d, reordered: %d\n", moved, reordered);
}

}  // namespace
}  // namespace forest::test
