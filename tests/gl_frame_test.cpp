// The frame: shadows where the CPU says they are, a term of 0 on faces turned from the sun, no acne with backside rendering (and acne
// without it), caster selection that changes nothing, every method clean, a sun below the horizon,
// hard cases, camera-relative props, n smoothed over time. The blur: gl_blur_test.cpp.
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "forest/core/scene.hpp"
#include "forest/render/debug_views.hpp"
#include "forest/render/frame.hpp"
#include "forest/shadows/focus_body.hpp"
#include "gl_test_support.hpp"
#include "test_paths.hpp"

namespace forest::test {
namespace {

using glm::dvec3;

constexpr int kWidth = 320, kHeight = 240;

dvec3 pixelPosition(const Camera& camera, int x, int y, float depth) {
  return test::pixelPosition(camera, x, y, depth, kWidth, kHeight);
}

Camera cameraAt(dvec3 position, double yawDeg, double pitchDeg, double far) {
  return test::cameraAt(position, yawDeg, pitchDeg, far, static_cast<double>(kWidth) / kHeight);
}

class FrameGl : public GlTest {};

TEST_F(FrameGl, BoxShadowOnAPlaneMatchesTheCpuProjection) {
  Scene scene;
  scene.sun.direction = glm::normalize(dvec3(0.35, -1.0, 0.25));
  scene.props.push_back({dvec3(-40, -1, -40), dvec3(40, 0, 40), dvec3(0.6)});  // the plane (top at y = 0)
  scene.props.push_back({dvec3(-2, 3, -2), dvec3(2, 5, 2), dvec3(0.8)});        // a box above it
  render::Frame frame(scene, kWidth, kHeight);
  const Camera camera = cameraAt({0, 22, 26}, 0.0, -42.0, 200.0);
  const Aabb box{scene.props[1].min, scene.props[1].max};
  for (shadows::ShadowMethod method : {shadows::ShadowMethod::Uniform, shadows::ShadowMethod::Lispsm, shadows::ShadowMethod::Tsm}) {
    render::FrameSettings settings;
    settings.method = method;
    settings.shadowMapSize = 1024;
    frame.render(camera, 0.0, settings);
    const CpuAgreement a =
        agreementWithCpuShadow(frame, camera, frame.readShadowTerm(), frame.objects().propIdBase(), {box}, -scene.sun.direction);
    const int wrong = a.wrong, checked = a.checked, shadowedPixels = a.shadowed;
    EXPECT_EQ(wrong, 0) << shadows::kShadowMethodNames.name(method) << ": " << wrong << " of " << checked << " plane pixels disagree";
    EXPECT_GT(shadowedPixels, 200) << shadows::kShadowMethodNames.name(method);  // the shadow is in view
    EXPECT_GT(checked, 20000) << shadows::kShadowMethodNames.name(method);
  }
}

// The term is forced to 0 where the drawn surface faces away from the sun, before any blur
// (DESIGN §4; the G-buffer's sun-facing flag), and a lit face keeps its light: a box on a plane,
// lit from +x, +y, +z, seen so that its averted −x face and its lit +z face both fill many pixels.
// Which face a pixel shows is decided on the CPU from its position on the box, not by the renderer.
TEST_F(FrameGl, TermIsZeroOnFacesTurnedFromTheSunAndOneOnLitFaces) {
  Scene scene;
  scene.sun.direction = glm::normalize(dvec3(-1.0, -0.6, -0.4));  // toward the sun: (1, 0.6, 0.4)
  scene.props.push_back({dvec3(-40, -1, -40), dvec3(40, 0, 40), dvec3(0.6)});  // the plane (top at y = 0)
  scene.props.push_back({dvec3(-2, 0, -2), dvec3(2, 4, 2), dvec3(0.8)});       // the box on it
  render::Frame frame(scene, kWidth, kHeight);
  // From (−7, 3, 9) toward (0, 2, 0): the −x and +z faces in view.
  const Camera camera = cameraAt({-7, 3, 9}, glm::degrees(std::atan2(-7.0, 9.0)), glm::degrees(std::atan2(-1.0, std::hypot(7.0, 9.0))), 200.0);
  const std::uint32_t boxId = frame.objects().propIdBase() + 1;
  for (shadows::ShadowMethod method : {shadows::ShadowMethod::Uniform, shadows::ShadowMethod::Lispsm}) {
    render::FrameSettings settings;
    settings.method = method;
    frame.render(camera, 0.0, settings);
    const std::vector<float> term = frame.readShadowTerm(), depth = frame.readDepth();
    const std::vector<std::uint32_t> ids = frame.readObjectIds();
    int averted = 0, avertedNonZero = 0, lit = 0, litDark = 0;
    for (int y = 0; y < kHeight; ++y)
      for (int x = 0; x < kWidth; ++x) {
        const size_t i = static_cast<size_t>(y) * kWidth + x;
        if (ids[i] != boxId) continue;
        const dvec3 p = pixelPosition(camera, x, y, depth[i]);
        const bool inside = p.y > 0.2 && p.y < 3.8;  // away from the face's top and bottom edges
        if (std::abs(p.x + 2.0) < 0.01 && inside && std::abs(p.z) < 1.8) {  // the −x face: N·l < 0
          ++averted;
          avertedNonZero += term[i] != 0.0f ? 1 : 0;
        } else if (std::abs(p.z - 2.0) < 0.01 && inside && std::abs(p.x) < 1.8) {  // the +z face, lit
          ++lit;
          litDark += term[i] < 0.5f ? 1 : 0;
        }
      }
    std::printf("[facing] %s: %d averted pixels, %d with a term; %d lit pixels, %d dark\n", shadows::kShadowMethodNames.name(method).data(),
                averted, avertedNonZero, lit, litDark);
    EXPECT_GT(averted, 300) << shadows::kShadowMethodNames.name(method);
    EXPECT_GT(lit, 300) << shadows::kShadowMethodNames.name(method);
    EXPECT_EQ(avertedNonZero, 0) << shadows::kShadowMethodNames.name(method);
    EXPECT_EQ(litDark, 0) << shadows::kShadowMethodNames.name(method);
  }
}

// CPU: does the ray from p toward the sun clear the full-resolution heightfield — by a margin
// growing with distance, 0.1·s up to `clearance` — so that no shadow edge is near?
bool sunClears(const terrain::Terrain& t, const dvec3& p, const dvec3& toSun, double clearance) {
  const Aabb b = t.bounds();
  for (double s = 0.5; s < 4000.0; s += 0.5 * t.heightfield().spacing()) {
    const dvec3 q = p + s * toSun;
    if (q.x < b.min.x || q.x > b.max.x || q.z < b.min.z || q.z > b.max.z || q.y > b.max.y + clearance) return true;
    if (t.heightAt(q.x, q.z) > q.y - std::min(clearance, 0.1 * s)) return false;
  }
  return true;
}

TEST_F(FrameGl, BacksideRenderingHasNoAcneAndFrontFacesDo) {
  Scene scene = loadScene(std::string(FOREST_REPO_DATA) + "/scenes/terrain.toml");
  scene.terrain->lod_error_pixels = 0.01;  // every tile at full resolution: the CPU heightfield is the drawn one
  const double elevation = glm::radians(5.0);
  scene.sun.direction = {std::cos(elevation) * 0.8, -std::sin(elevation), std::cos(elevation) * 0.6};
  render::Frame frame(scene, kWidth, kHeight);
  const terrain::Terrain& t = *frame.terrain();
  // The sun behind the camera (yaw 233°: forward (0.8, 0, 0.6), along the light), 150 m up,
  // looking down over slopes that face the sun, across tile seams.
  Camera camera = cameraAt({0, 0, 0}, 233.13, -35.0, 3000.0);
  camera.position.y = t.heightAt(0, 0) + 150.0;
  const dvec3 toSun = -scene.sun.direction;
  for (shadows::ShadowMethod method : {shadows::ShadowMethod::Lispsm, shadows::ShadowMethod::Tsm}) {
    int violations[2] = {0, 0}, checked = 0;
    for (int pass = 0; pass < 2; ++pass) {
      render::FrameSettings settings;
      settings.method = method;
      settings.backside = pass == 0;
      settings.culling = culling::CullingStrategy::Frustum;
      frame.render(camera, 0.0, settings);
      const std::vector<float> term = frame.readShadowTerm();
      const std::vector<float> depth = frame.readDepth();
      const std::vector<std::uint32_t> ids = frame.readObjectIds();
      int facing = 0;
      for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x) {
          const size_t i = static_cast<size_t>(y) * kWidth + x;
          if (ids[i] == 0) continue;
          const dvec3 p = pixelPosition(camera, x, y, depth[i]);
          if (glm::dot(t.normalAt(p.x, p.z), toSun) <= 0.2) continue;
          ++facing;
          if (!sunClears(t, p, toSun, 1.5)) continue;
          if (pass == 0) ++checked;
          if (term[i] < 0.5f) ++violations[pass];
        }
      if (pass == 0) std::printf("[acne] %s: %d pixels face the sun (N·L > 0.2)\n", shadows::kShadowMethodNames.name(method).data(), facing);
    }
    std::printf("[acne] %s: %d lit pixels checked: %d shadowed with backside rendering, %d with front faces\n",
                shadows::kShadowMethodNames.name(method).data(), checked, violations[0], violations[1]);
    EXPECT_GT(checked, 1000);
    EXPECT_EQ(violations[0], 0) << shadows::kShadowMethodNames.name(method);
    EXPECT_GT(violations[1], checked / 20) << shadows::kShadowMethodNames.name(method);  // front faces, no bias: acne (the test can fail)
  }
}

// The casters of the visible receivers, grown by what the filter reads (r + 1 texels per axis for
// --pcf r, shaders/shadow_lookup.frag), shadow exactly what all casters shadow: the term is equal
// pixel for pixel, for every PCF radius, along 30 views of the default forest (ground level and
// 40 m up, three methods).
TEST_F(FrameGl, CasterSelectionChangesNoShadowForAnyFilterAlongThirtyViews) {
  // 300 frames of the engine's own logic: run once, on EGL (the backends differ in their context only).
  if (backendUnderTest() != "egl") GTEST_SKIP() << "checked on the egl backend";
  DefaultForestWalk walk(kWidth, kHeight);
  render::Frame& frame = walk.frame;
  const Camera& camera = walk.camera;
  int views = 0, fewer = 0;
  for (int v = 0; v < 30; ++v) {
    walk.step(v);
    if (v % kSweepStride != 0) continue;
    for (int pcf = 0; pcf <= 4; ++pcf) {
      render::FrameSettings settings;
      settings.method = v % 3 == 0 ? shadows::ShadowMethod::Uniform : v % 3 == 1 ? shadows::ShadowMethod::Lispsm : shadows::ShadowMethod::Tsm;
      settings.shadowMapSize = 1024;
      settings.pcfRadius = pcf;
      const CasterComparison c = compareSelectedWithAllCasters(frame, camera, 0.5 * v, settings);
      EXPECT_EQ(c.differ, 0) << "view " << v << ", pcf " << pcf << ": " << c.differ << " pixels";
      fewer += c.selectedCasters < c.allCasters ? 1 : 0;
      ++views;
    }
  }
  EXPECT_EQ(views, 150 / kSweepStride);
  EXPECT_GT(fewer, 125 / kSweepStride);  // the selection does leave casters out
}

// The filter's reach at the edge of the view: a noon sun, the camera looking straight down on a
// thin plane, and a caster outside the view whose shadow starts 3.4 texels beyond the lookup of
// the rightmost pixels (1.8 texels beyond the visible plane's edge, inside the map's border). A
// PCF of radius r reads texel centres less than r + 1 texels from a lookup, so r ≤ 1 cannot see
// it and r = 4 must (its first covered centre is < 4.4 texels away); for every r the term with the
// selected casters equals the term with all casters. (The former fixed 1.5-texel growth left the
// caster out.)
TEST_F(FrameGl, CasterJustBeyondTheVisibleEdgeIsSelectedForTheFilterThatReadsIt) {
  Scene scene;
  scene.sun.direction = dvec3(0.0, -1.0, 0.0);
  scene.props.push_back({dvec3(-50, -1e-3, -50), dvec3(50, 0, 50), dvec3(0.6)});  // thin: its box is the visible surface
  render::Frame probe(scene, kWidth, kHeight);
  const Camera camera = cameraAt({0, 10, 0}, 0.0, -90.0, 100.0);
  render::FrameSettings settings;
  settings.method = shadows::ShadowMethod::Uniform;
  settings.shadowMapSize = 1024;
  settings.culling = culling::CullingStrategy::Frustum;
  const double halfWidth = 10.0 * std::tan(glm::radians(30.0)) * kWidth / kHeight;  // the view's edge on the plane
  const double lastPixel = halfWidth * (1.0 - 1.0 / kWidth);                          // the rightmost pixel centres
  for (int pcf = 0; pcf <= 4; ++pcf) {
    settings.pcfRadius = pcf;
    probe.render(camera, 0.0, settings);  // where the map's texels lie (the caster will not change B)
    const glm::dmat4& m = probe.shadowSetup().worldToShadowClip;
    auto texelAt = [&](double x) { return glm::dvec2(m * glm::dvec4(x, 0.0, 0.0, 1.0)) * (0.5 * 1024); };
    const double texelsPerMetre = glm::length(texelAt(halfWidth + 1.0) - texelAt(halfWidth));
    const double start = lastPixel + 3.4 / texelsPerMetre;
    const double beyondEdge = (start - halfWidth) * texelsPerMetre;
    ASSERT_GT(beyondEdge, 1.5);
    ASSERT_LT(beyondEdge, 2.0);  // inside the map's border (≥ 2 texels): drawn when selected
    Scene withCaster = scene;
    withCaster.props.push_back({dvec3(start, 4, -2), dvec3(start + 1.0, 5, 2), dvec3(0.8)});
    render::Frame frame(withCaster, kWidth, kHeight);
    settings.casters = render::CasterSelection::Receivers;
    frame.render(camera, 0.0, settings);
    const std::vector<float> withSelected = frame.readShadowTerm();
    settings.casters = render::CasterSelection::All;
    frame.resetHistory();
    frame.render(camera, 0.0, settings);
    const std::vector<float> withAll = frame.readShadowTerm();
    int differ = 0, touched = 0;
    for (size_t i = 0; i < withAll.size(); ++i) {
      differ += withSelected[i] != withAll[i] ? 1 : 0;
      touched += withAll[i] < 1.0f ? 1 : 0;
    }
    std::printf("[filter reach] pcf %d: %d pixels read the caster's shadow, %d differ with the selected casters\n", pcf,
                touched, differ);
    EXPECT_EQ(differ, 0) << "pcf " << pcf;
    if (pcf <= 1) {
      EXPECT_EQ(touched, 0) << "pcf " << pcf;
    }
    if (pcf == 4) {
      EXPECT_GT(touched, 0) << "pcf 4 reads the caster's shadow from the edge pixels";
    }
  }
}

TEST_F(FrameGl, EveryMethodIsCleanAndASunBelowTheHorizonLeavesAmbient) {
  Scene scene = loadScene(std::string(FOREST_REPO_DATA) + "/scenes/forest.toml");
  render::Frame frame(scene, kWidth, kHeight);
  Camera camera = frame.startCamera();
  camera.aspect = static_cast<double>(kWidth) / kHeight;
  for (shadows::ShadowMethod method :
       {shadows::ShadowMethod::Uniform, shadows::ShadowMethod::UniformStable, shadows::ShadowMethod::Lispsm,
        shadows::ShadowMethod::Tsm, shadows::ShadowMethod::TsmIterative}) {
    for (int step = 0; step < 4; ++step) {
      camera.position.x += 2.0;
      camera.yaw += glm::radians(10.0);
      render::FrameSettings settings;
      settings.method = method;
      settings.shadowMapSize = 1024;
      frame.render(camera, step, settings);
      for (float v : frame.readShadowTerm()) ASSERT_TRUE(std::isfinite(v) && v >= 0.0f && v <= 1.0f);
    }
  }
  const Image8 lit = frame.readColor();
  scene.sun.direction = glm::normalize(dvec3(0.3, 0.5, 0.2));  // travelling upward: the sun is below the horizon
  const render::FrameStats night = frame.render(camera, 3.0, render::FrameSettings{});
  EXPECT_TRUE(night.sunBelowHorizon);
  const Image8 dark = frame.readColor();
  const std::vector<float> term = frame.readShadowTerm();
  const std::vector<std::uint32_t> ids = frame.readObjectIds();
  int ground = 0;
  for (size_t i = 0; i < ids.size(); ++i) {
    if (ids[i] == 0) continue;
    ++ground;
    ASSERT_EQ(term[i], 0.0f);  // no sun anywhere
  }
  EXPECT_GT(ground, 1000);
  for (size_t i = 0; i < lit.pixels.size(); ++i) ASSERT_LE(dark.pixels[i], lit.pixels[i] + 1);  // ambient only: never brighter
}

TEST_F(FrameGl, TopDownDiagramDrawsTheSetupAndTheLightFrustumHoldsB) {
  const Scene scene = loadScene(std::string(FOREST_REPO_DATA) + "/scenes/forest.toml");
  render::Frame frame(scene, kWidth, kHeight);
  Camera camera = frame.startCamera();
  camera.aspect = static_cast<double>(kWidth) / kHeight;
  for (shadows::ShadowMethod method : {shadows::ShadowMethod::Uniform, shadows::ShadowMethod::Lispsm, shadows::ShadowMethod::Tsm}) {
    render::FrameSettings settings;
    settings.method = method;
    settings.shadowMapSize = 1024;
    frame.render(camera, 0.0, settings);
    // The light frustum drawn in the diagram holds the focus body — B computed here from the
    // frame's own inputs (the camera up to z_f, the sun, S, the visible receivers' bounds, a tile's
    // by its blocks in view) — and is tight: B touches each of its four sides (uniform: within the
    // map's border, 2 texels of 1024).
    const auto corners = render::lightFrustumCorners(frame.shadowSetup());
    Aabb sceneBox;
    for (const Aabb& b : frame.objects().boxes()) sceneBox.extend(b);
    const Aabb receiverBox = visibleReceiverBounds(frame, camera);
    const ConvexBody body = shadows::computeFocusBody(frame.shadowCamera(), glm::normalize(scene.sun.direction), sceneBox, receiverBox);
    ASSERT_FALSE(body.empty());
    dvec3 centre(0.0);
    for (const dvec3& c : corners) centre += c / 8.0;
    // Faces of the hexahedron: the four corners sharing one bit of their index; plane through
    // three of them, oriented away from the centre.
    double size = 0.0;
    for (const dvec3& c : corners) size = std::max(size, glm::distance(c, centre));
    for (int bit = 0; bit < 3; ++bit)
      for (int value = 0; value < 2; ++value) {
        std::vector<dvec3> face;
        for (int i = 0; i < 8; ++i)
          if (((i >> bit) & 1) == value) face.push_back(corners[static_cast<size_t>(i)]);
        dvec3 normal = glm::normalize(glm::cross(face[1] - face[0], face[2] - face[0]));
        if (glm::dot(normal, centre - face[0]) > 0.0) normal = -normal;
        double nearest = 1e300, outside = -1e300;
        for (const dvec3& v : body.vertices()) {
          const double distance = glm::dot(v - face[0], normal);
          outside = std::max(outside, distance);
          nearest = std::min(nearest, -distance);
        }
        EXPECT_LE(outside, 1e-6 * size) << shadows::kShadowMethodNames.name(method) << ": B outside face " << bit << "/" << value;
        // x, y sides of the orthographic map, whose texels have one size everywhere (a warped
        // map's border texels span metres at its far end).
        if (bit < 2 && method == shadows::ShadowMethod::Uniform) {
          EXPECT_LE(nearest, 2.0 * (2.0 + 1.0) / 1024.0 * size) << shadows::kShadowMethodNames.name(method) << ": B does not reach side " << bit << "/" << value;
        }
      }
    const Image8 diagram = render::topDownDiagram(frame, scene.sun.direction, 512);
    ASSERT_EQ(diagram.width, 512);
    ASSERT_EQ(diagram.height, 512 + render::kTopDownLegendHeight);
    // Each element leaves pixels of its colour in the diagram (below the legend band): B's outline
    // (blue), the light frustum (red), the view frustum (black), casters (orange).
    int blue = 0, red = 0, black = 0, orange = 0;
    for (int y = render::kTopDownLegendHeight; y < diagram.height; ++y)
      for (int x = 0; x < diagram.width; ++x) {
        const int r = diagram.at(x, y, 0), g = diagram.at(x, y, 1), b = diagram.at(x, y, 2);
        blue += b > 200 && r < 60 ? 1 : 0;
        red += r > 200 && g < 40 && b < 40 ? 1 : 0;
        black += r + g + b < 30 ? 1 : 0;
        orange += r > 230 && g > 120 && g < 160 && b < 30 ? 1 : 0;
      }
    EXPECT_GT(blue, 100) << shadows::kShadowMethodNames.name(method);
    EXPECT_GT(red, 100) << shadows::kShadowMethodNames.name(method);
    EXPECT_GT(black, 100) << shadows::kShadowMethodNames.name(method);
    EXPECT_GT(orange, 100) << shadows::kShadowMethodNames.name(method);
  }
}

// DESIGN §6 render-level hard cases through the full frame: no GL errors (GlTest), finite shadow
// matrices and terms, and on the plane the term the CPU's rays give on every pixel away from the
// shadow's edges (agreementWithCpuShadow); looking straight up: sky only, lit, the sky's colour.
TEST_F(FrameGl, HardCasesThroughTheFullFrame) {
  struct Case {
    const char* name;
    dvec3 sun;
    dvec3 offset;    // the whole scene and camera moved here
    double pitchDeg;
    bool shadowOnPlane = true;  // the box (3–5 m up) shadows the 120 m plane in view
  };
  const double half = glm::radians(0.5);
  const Case cases[] = {
      {"dueling frusta: looking along the light", dvec3(0.0, -1.0, 0.0), dvec3(0.0), -89.9},
      {"looking straight down, oblique sun", glm::normalize(dvec3(0.5, -1.0, 0.3)), dvec3(0.0), -90.0},
      {"looking straight up", glm::normalize(dvec3(0.3, -1.0, 0.2)), dvec3(0.0), 90.0},
      // The box's shadow falls 3 m / tan 0.5° ≈ 344 m away, off the plane: every plane pixel lit.
      {"sun 0.5° above the horizon", dvec3(std::cos(half), -std::sin(half), 0.0), dvec3(0.0), -30.0, false},
      {"camera 1e5 m from the origin", glm::normalize(dvec3(0.3, -1.0, 0.2)), dvec3(1e5, 0.0, -1e5), -30.0},
  };
  for (const Case& c : cases) {
    Scene scene;
    scene.sun.direction = c.sun;
    scene.props.push_back({c.offset + dvec3(-60, -1, -60), c.offset + dvec3(60, 0, 60), dvec3(0.6)});
    scene.props.push_back({c.offset + dvec3(-2, 3, -2), c.offset + dvec3(2, 5, 2), dvec3(0.8)});
    render::Frame frame(scene, kWidth, kHeight);
    const Camera camera = cameraAt(c.offset + dvec3(1.0, 14.0, 9.0), 0.0, c.pitchDeg, 400.0);
    for (shadows::ShadowMethod method : {shadows::ShadowMethod::Uniform, shadows::ShadowMethod::Lispsm, shadows::ShadowMethod::Tsm}) {
      render::FrameSettings settings;
      settings.method = method;
      settings.shadowMapSize = 1024;
      settings.blurRadius = 2.0;
      const render::FrameStats stats = frame.render(camera, 0.0, settings);
      const std::string where = std::string(c.name) + " / " + std::string(shadows::kShadowMethodNames.name(method));
      const glm::dmat4& m = frame.shadowSetup().worldToShadowClip;
      for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) ASSERT_TRUE(std::isfinite(m[i][j])) << where;
      ASSERT_TRUE(std::isfinite(stats.shadow.n)) << where;
      const std::vector<float> blurred = frame.readBlurredShadowTerm(), term = frame.readShadowTerm();
      for (size_t i = 0; i < term.size(); ++i) ASSERT_TRUE(std::isfinite(blurred[i]) && std::isfinite(term[i])) << where;
      const Aabb box{scene.props[1].min, scene.props[1].max};
      if (c.pitchDeg > 60.0) {
        // Looking straight up from above the box: nothing but sky, whose term is 1 and whose
        // colour is the sky's along each pixel's ray (no garbage from the setup).
        const std::vector<std::uint32_t> ids = frame.readObjectIds();
        const Image8 color = frame.readColor();  // top row first
        for (size_t i = 0; i < ids.size(); ++i) {
          ASSERT_EQ(ids[i], 0u) << where;
          ASSERT_EQ(term[i], 1.0f) << where;
          const int x = static_cast<int>(i % kWidth), y = static_cast<int>(i / kWidth);  // bottom row first
          const dvec3 ray = glm::normalize(pixelPosition(camera, x, y, 0.5f) - camera.position);
          if (const double cosine = glm::dot(ray, -c.sun); cosine > 0.99985 && cosine < 0.99990) continue;  // the disc's edge
          const dvec3 sky = skyDisplay(ray, scene.render.sky_color, -c.sun, scene.sun.color, true);
          const size_t top = static_cast<size_t>(kHeight - 1 - y) * kWidth + static_cast<size_t>(x);
          for (int k = 0; k < 3; ++k) ASSERT_NEAR(color.pixels[top * 4 + static_cast<size_t>(k)], sky[k], 1.5) << where;
        }
        continue;
      }
      // On the plane: the term where the CPU says, everywhere away from the shadow's edges.
      const CpuAgreement a = agreementWithCpuShadow(frame, camera, term, frame.objects().propIdBase(), {box}, -c.sun);
      EXPECT_EQ(a.wrong, 0) << where << ": " << a.wrong << " of " << a.checked << " plane pixels disagree";
      EXPECT_GT(a.checked, 1000) << where;
      if (c.shadowOnPlane) {
        EXPECT_GT(a.shadowed, 20) << where;  // the box's shadow is in view and checked
      } else {
        EXPECT_EQ(a.shadowed, 0) << where;
      }
      EXPECT_GT(a.checked - a.shadowed, 20) << where;
    }
  }
}

// DESIGN §4: everything the GPU gets is camera-relative, so a scene 1e5 m from the origin renders
// like the same scene at the origin. Small boxes close to the eye show it: at 1e5 m a float32
// coordinate is a multiple of 7.8 mm, several pixels here (1.1 mm per pixel at 0.3 m).
TEST_F(FrameGl, PropsFarFromTheOriginRenderLikePropsAtTheOrigin) {
  const dvec3 offset(1e5 + 0.37, 0.0, -1e5 - 0.61);
  Image8 images[2];
  std::vector<std::uint32_t> ids[2];
  for (int k = 0; k < 2; ++k) {
    const dvec3 o = k == 0 ? dvec3(0.0) : offset;
    Scene scene;
    scene.sun.direction = glm::normalize(dvec3(0.3, -1.0, 0.2));
    scene.props.push_back({o + dvec3(-3, -0.1, -3), o + dvec3(3, 0, 1), dvec3(0.6)});  // ground
    for (int i = 0; i < 5; ++i) {
      const dvec3 at = o + dvec3(-0.12 + 0.061 * i, 0.02 + 0.013 * i, -0.31 - 0.043 * i);
      scene.props.push_back({at, at + dvec3(0.043, 0.051, 0.037), dvec3(0.9, 0.5, 0.2)});
    }
    render::Frame frame(scene, kWidth, kHeight);
    Camera camera = cameraAt(o + dvec3(0.013, 0.12, 0.007), 0.0, -15.0, 20.0);
    camera.near = 0.02;
    render::FrameSettings settings;
    settings.shadowMapSize = 1024;
    frame.render(camera, 0.0, settings);
    images[k] = frame.readColor();
    ids[k] = frame.readObjectIds();
  }
  // Pixels away from the reference's edges (no other object within 1 pixel).
  int compared = 0, equal = 0, boxes = 0;
  for (int y = 1; y + 1 < kHeight; ++y)
    for (int x = 1; x + 1 < kWidth; ++x) {
      const size_t i = static_cast<size_t>(y) * kWidth + x;  // ids: bottom row first
      bool edge = false;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) edge = edge || ids[0][i + static_cast<size_t>(dy * kWidth + dx)] != ids[0][i];
      if (edge) continue;
      ++compared;
      boxes += ids[0][i] > 1 ? 1 : 0;
      const int row = kHeight - 1 - y;  // readColor: top row first
      bool same = true;
      for (int c = 0; c < 4; ++c) same = same && images[0].at(x, row, c) == images[1].at(x, row, c);
      equal += same ? 1 : 0;
    }
  std::printf("[far props] %d of %d pixels away from edges equal (%d on the small boxes)\n", equal, compared, boxes);
  EXPECT_GT(boxes, 2000);  // the small boxes fill a good part of the view
  EXPECT_GE(equal, compared - compared / 1000) << compared - equal << " pixels differ";
}

// n is smoothed over time in both directions (§9.2.5; shadows::kNearDistanceSmoothing): when the
// visible set's z_f jumps up or down, n moves 20% of the way to eq. 8.13's value per frame —
// never the whole way at once, as before when z_f dropped — and monotonically.
TEST_F(FrameGl, NearDistanceMovesAFifthOfTheWayPerFrameWhenZfJumpsEitherWay) {
  Scene scene;
  scene.sun.direction = dvec3(0.0, -1.0, 0.0);
  scene.props.push_back({dvec3(-20, -1, -40), dvec3(20, 0, 5), dvec3(0.6)});       // ground to 40 m
  scene.props.push_back({dvec3(-10, 0, -151), dvec3(10, 12, -150), dvec3(0.8)});   // a wall at 150 m
  render::Frame frame(scene, kWidth, kHeight);
  const Camera camera = cameraAt({0, 2, 0}, 0.0, 0.0, 400.0);
  render::FrameSettings settings;
  settings.culling = culling::CullingStrategy::Frustum;
  settings.method = shadows::ShadowMethod::Lispsm;
  std::vector<render::FrameStats> frames;
  auto run = [&](int count) {
    for (int i = 0; i < count; ++i) frames.push_back(frame.render(camera, 0.0, settings));
  };
  run(25);                                    // steady with the wall in view
  const Aabb wall{scene.props[1].min, scene.props[1].max};
  scene.props[1] = {dvec3(-10, 0, 100), dvec3(10, 12, 101), dvec3(0.8)};  // behind the camera: z_f drops
  frame.propsMoved();
  run(25);
  scene.props[1] = {wall.min, wall.max, dvec3(0.8)};  // back: z_f jumps up
  frame.propsMoved();
  run(25);
  ASSERT_GT(frames[24].farDepth, 2.5 * frames[25].farDepth);  // the jumps are real
  ASSERT_GT(frames[50].farDepth, 2.5 * frames[49].farDepth);
  for (size_t k = 1; k < frames.size(); ++k) {
    const double previous = frames[k - 1].shadow.n, expected = previous + 0.2 * (frames[k].shadow.nOptimal - previous);
    EXPECT_NEAR(frames[k].shadow.n, expected, 1e-9 * expected) << "frame " << k;
  }
  for (size_t jump : {size_t{25}, size_t{50}}) {
    const double before = frames[jump - 1].shadow.n, target = frames[jump].shadow.nOptimal;
    ASSERT_GT(std::abs(target - before), 0.1 * before) << "n changes with z_f";
    const double firstStep = (frames[jump].shadow.n - before) / (target - before);
    std::printf("[n smoothing] jump at frame %zu: z_f %.1f -> %.1f, n %.3f -> eq. 8.13 %.3f, first step %.3f of the way\n", jump,
                frames[jump - 1].farDepth, frames[jump].farDepth, before, target, firstStep);
    EXPECT_NEAR(firstStep, 0.2, 1e-9) << "jump at frame " << jump;
    for (size_t k = jump; k < jump + 24; ++k)  // monotone towards the new value
      EXPECT_GE((frames[k + 1].shadow.n - frames[k].shadow.n) * (target - before), 0.0) << "frame " << k;
    EXPECT_LT(std::abs(frames[jump + 24].shadow.n - target), 0.01 * std::abs(target - before));  // 0.8²⁵ < 0.4%
  }
}

}  // namespace
}  // namespace forest::test
