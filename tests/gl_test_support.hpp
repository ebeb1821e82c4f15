#pragma once
// GL test harness: gl_tests runs with --gl=<backend>; one context per process, created before the
// first test. Every test derives from GlTest, which fails the test on any KHR_debug error.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "forest/core/bounds.hpp"
#include "forest/core/camera.hpp"
#include "forest/core/frustum.hpp"
#include "forest/gl/context.hpp"
#include "forest/gl/debug.hpp"
#include "forest/gl/gl.hpp"
#include "forest/gl/objects.hpp"
#include "forest/core/scene.hpp"
#include "forest/render/frame.hpp"
#include "test_paths.hpp"

namespace forest::test {

// The long sweeps of the engine's own logic (30-view caster comparisons, split checks, the
// allocation walk) take every kSweepStride-th case. The Release run checks every case; the ASan +
// UBSan run looks for memory errors and undefined behaviour, which the same code paths show at a
// third of the cases, in a third of the time.
#ifdef FOREST_TEST_SANITIZED
inline constexpr int kSweepStride = 3;
#else
inline constexpr int kSweepStride = 1;
#endif

// The backend named on the command line ("egl", "osmesa", "window").
const std::string& backendUnderTest();
gl::Context& context();

class GlTest : public ::testing::Test {
 protected:
  void SetUp() override {
    context().makeCurrent();
    gl::resetDebugErrors();
  }
  void TearDown() override {
    glFinish();
    EXPECT_EQ(gl::debugErrorCount(), 0u) << "GL errors: " << joinedErrors();
  }
  static std::string joinedErrors() {
    std::string all;
    for (const auto& m : gl::debugErrorMessages()) all += m + "; ";
    return all;
  }
};

// World position of pixel (x, y) (bottom-up rows) of a width × height image from its reversed-Z depth.
inline glm::dvec3 pixelPosition(const Camera& camera, int x, int y, float depth, int width, int height) {
  const glm::dmat4 inverse = glm::inverse(camera.projection() * camera.view());
  const glm::dvec4 h = inverse * glm::dvec4(2.0 * (x + 0.5) / width - 1.0, 2.0 * (y + 0.5) / height - 1.0, depth, 1.0);
  return glm::dvec3(h) / h.w;
}

// The sky's display colour (0–255) along the unit view direction d: the closed form of
// shaders/lighting.frag's skyRadiance — the zenith (`skyColor`, display values, γ 2.2) fading to
// mix(zenith, (0.75, 0.8, 0.85), 0.55) at the horizon by smoothstep(0, 0.6, d.y), darker below it,
// plus the sun's glow 0.6 c^400 + 0.08 c^8 and its disc (12 × the sun's colour, cos θ ≥ 0.9999),
// c = d · toSun. Pixels whose c lies in the disc's edge ramp (cos 1°…cos 0.8°) are not compared.
inline glm::dvec3 skyDisplay(const glm::dvec3& d, const glm::dvec3& skyColor, const glm::dvec3& toSun, const glm::dvec3& sunColor,
                             bool sunUp) {
  const glm::dvec3 zenith = glm::pow(skyColor, glm::dvec3(2.2));
  const glm::dvec3 horizon = zenith + 0.55 * (glm::dvec3(0.75, 0.8, 0.85) - zenith);
  const double t = std::clamp(d.y / 0.6, 0.0, 1.0), s = t * t * (3.0 - 2.0 * t);
  glm::dvec3 sky = d.y >= 0.0 ? horizon + s * (zenith - horizon) : horizon * (1.0 + 0.3 * d.y);
  if (sunUp) {
    const double c = glm::dot(d, toSun), cp = std::max(c, 0.0);
    sky += sunColor * ((c >= 0.99990 ? 12.0 : 0.0) + 0.6 * std::pow(cp, 400.0) + 0.08 * std::pow(cp, 8.0));
  }
  return 255.0 * glm::pow(glm::clamp(sky, 0.0, 1.0), glm::dvec3(1.0 / 2.2));
}

// Whether the ray from `origin` (excluding its first 1e-6) meets the box (slab test).
inline bool rayHitsBox(const glm::dvec3& origin, const glm::dvec3& direction, const Aabb& box) {
  double enter = 1e-6, leave = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a) {
    if (direction[a] == 0.0) {
      if (origin[a] < box.min[a] || origin[a] > box.max[a]) return false;
      continue;
    }
    double t0 = (box.min[a] - origin[a]) / direction[a], t1 = (box.max[a] - origin[a]) / direction[a];
    if (t0 > t1) std::swap(t0, t1);
    enter = std::max(enter, t0);
    leave = std::min(leave, t1);
  }
  return enter <= leave;
}

// A camera at `position` with yaw and pitch in degrees, near 0.2, the given far and aspect.
inline Camera cameraAt(glm::dvec3 position, double yawDeg, double pitchDeg, double far, double aspect) {
  Camera c;
  c.position = position;
  c.yaw = glm::radians(yawDeg);
  c.pitch = glm::radians(pitchDeg);
  c.aspect = aspect;
  c.near = 0.2;
  c.far = far;
  return c;
}

// The geometry pass's target in tests: object IDs (GL_R32UI) and reversed-Z float depth.
// The frame's shadow term on a plane's pixels against the CPU's ray toward the sun past boxes,
// away from the CPU's shadow edges. The band left out: max(2 px, 1.5 projected texels) of the
// slice the pixel reads (of both in a blend band) — the caster's edge is rasterised at texel
// centres (half a texel) and 2×2 PCF blends over one more texel, so the term's 0.5 crossing lies
// within 1.5 texels of the true edge (2 px: the pixel grid).
struct CpuAgreement {
  int checked = 0, wrong = 0, shadowed = 0;
  std::vector<double> checkedDepths;  // eye depth of each checked pixel
  std::vector<int> checkedStates;     // 1: in the CPU's shadow
};
inline CpuAgreement agreementWithCpuShadow(const render::Frame& frame, const Camera& camera, const std::vector<float>& term,
                                           std::uint32_t plane, const std::vector<Aabb>& boxes, const glm::dvec3& toSun) {
  const int width = frame.width(), height = frame.height();
  const std::vector<std::uint32_t> ids = frame.readObjectIds();
  const std::vector<float> depth = frame.readDepth();
  auto position = [&](int x, int y) { return pixelPosition(camera, x, y, depth[static_cast<size_t>(y) * width + x], width, height); };
  std::vector<int> cpu(term.size(), -1);  // 1: the ray toward the sun hits a box
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const size_t i = static_cast<size_t>(y) * width + x;
      if (ids[i] != plane) continue;
      cpu[i] = 0;
      for (const Aabb& box : boxes) cpu[i] |= rayHitsBox(position(x, y), toSun, box) ? 1 : 0;
    }
  CpuAgreement a;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const size_t i = static_cast<size_t>(y) * width + x;
      if (cpu[i] < 0) continue;
      const glm::dvec3 p = position(x, y);
      const double eyeDepth = glm::dot(p - camera.position, camera.forward());
      auto screen = [&](const glm::dvec3& q) {
        const glm::dvec4 h = camera.projection() * camera.view() * glm::dvec4(q, 1.0);
        return glm::dvec2(h) / h.w * glm::dvec2(0.5 * width, 0.5 * height);
      };
      double pixelsPerTexel = 0.0;
      for (int slice = 0; slice < frame.cascadeCount(); ++slice) {
        const Camera& reach = frame.shadowCamera(slice);  // the slice's B covers [near, far]
        if (frame.cascadeCount() > 1 && (eyeDepth < reach.near || eyeDepth > reach.far)) continue;
        const glm::dmat4& toShadow = frame.shadowSetup(slice).worldToShadowClip;
        const int mapSize = frame.shadowMapSize(slice);
        auto texel = [&](const glm::dvec3& q) {
          const glm::dvec4 h = toShadow * glm::dvec4(q, 1.0);
          return glm::dvec2(h) / h.w * (0.5 * mapSize);
        };
        for (const glm::dvec3& d : {glm::dvec3(0.01, 0, 0), glm::dvec3(0, 0, 0.01)})
          pixelsPerTexel = std::max(pixelsPerTexel, glm::length(screen(p + d) - screen(p)) / glm::length(texel(p + d) - texel(p)));
      }
      const int band = static_cast<int>(std::ceil(std::max(2.0, 1.5 * pixelsPerTexel)));
      bool nearEdge = false;
      for (int dy = -band; dy <= band && !nearEdge; ++dy)
        for (int dx = -band; dx <= band && !nearEdge; ++dx) {
          const int nx = x + dx, ny = y + dy;
          if (nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
          const int other = cpu[static_cast<size_t>(ny) * width + nx];
          nearEdge = other >= 0 && other != cpu[i];
        }
      if (nearEdge) continue;
      ++a.checked;
      a.shadowed += cpu[i];
      a.checkedDepths.push_back(eyeDepth);
      a.checkedStates.push_back(cpu[i]);
      if ((term[i] < 0.5f) != (cpu[i] == 1)) ++a.wrong;
    }
  return a;
}

// The same frame rendered with the selected casters and with all casters, no history (smoothed n
// and splits, CHC) in between: how many pixels of the shadow term differ, and the caster counts.
struct CasterComparison {
  int differ = 0;
  int selectedCasters = 0, allCasters = 0;
  long long selectedTerrainTriangles = 0, allTerrainTriangles = 0;  // of the shadow pass
  std::vector<std::uint32_t> selected;                               // the selected casters, every slice's
};
inline CasterComparison compareSelectedWithAllCasters(render::Frame& frame, const Camera& camera, double time,
                                                      render::FrameSettings settings,
                                                      render::CasterSelection selection = render::CasterSelection::Receivers,
                                                      int framesBefore = 0) {
  settings.culling = culling::CullingStrategy::Frustum;
  settings.casters = selection;
  frame.resetHistory();
  CasterComparison c;
  // Frames before at the same view: what a frame hands the next (the trees that counted in its map).
  for (int f = 0; f < framesBefore; ++f) frame.render(camera, time, settings);
  const render::FrameStats selected = frame.render(camera, time, settings);
  c.selectedCasters = selected.casterObjects;
  c.selectedTerrainTriangles = selected.shadowTerrainTriangles;
  for (int slice = 0; slice < frame.cascadeCount(); ++slice) {
    const std::vector<std::uint32_t> casters = frame.casters(slice);  // a copy: read back on the GPU path
    c.selected.insert(c.selected.end(), casters.begin(), casters.end());
  }
  const std::vector<float> withSelected = frame.readShadowTerm();
  settings.casters = render::CasterSelection::All;
  frame.resetHistory();
  const render::FrameStats all = frame.render(camera, time, settings);
  c.allCasters = all.casterObjects;
  c.allTerrainTriangles = all.shadowTerrainTriangles;
  const std::vector<float> withAll = frame.readShadowTerm();
  for (size_t i = 0; i < withAll.size(); ++i) c.differ += withSelected[i] != withAll[i] ? 1 : 0;
  return c;
}

// View v of a walk over the default forest's terrain: 3 m east and 4 m north of the one before,
// 7° further left, 1.7 m over the ground — 40 m over it every tenth view.
inline void stepForestView(Camera& camera, const terrain::Terrain& terrain, int v) {
  camera.position.x += 3.0;
  camera.position.z -= 4.0;
  camera.position.y = terrain.heightAt(camera.position.x, camera.position.z) + (v % 10 == 9 ? 40.0 : 1.7);
  camera.yaw += glm::radians(7.0);
}

// The default forest (data/scenes/forest.toml) in a frame of width × height, and the camera of a
// walk over it from its start (step(v): stepForestView).
// The bounds of the last frame's visible receivers as the shadow setup takes them: each visible
// tree's or prop's box, and each visible terrain tile's blocks at the level the eye's LOD draws it
// that meet `camera`'s frustum (Terrain::blockBoxes).
inline Aabb visibleReceiverBounds(const render::Frame& frame, const Camera& camera) {
  Aabb bounds;
  const terrain::Terrain* terrain = frame.terrain();
  const std::optional<terrain::TerrainLod> lod = terrain ? std::optional(terrain->lodFor(camera, frame.height())) : std::nullopt;
  const Frustum view(camera);
  for (std::uint32_t o : frame.visibleObjects()) {
    const render::SceneObjects::Object& object = frame.objects().objects()[o];
    if (!terrain || object.kind != render::SceneObjects::Kind::Tile) {
      bounds.extend(frame.objects().boxes()[o]);
      continue;
    }
    const int tile = static_cast<int>(object.index);
    for (const Aabb& block : terrain->blockBoxes(tile, terrain->tileLevel(tile, *lod)))
      if (view.mayIntersect(block)) bounds.extend(block);
  }
  return bounds;
}

struct DefaultForestWalk {
  Scene scene;
  render::Frame frame;
  Camera camera;
  // `windStrength`: the scene's unless given (0: trees that stand still).
  DefaultForestWalk(int width, int height, std::optional<double> windStrength = std::nullopt)
      : scene(withWind(loadScene(std::string(FOREST_REPO_DATA) + "/scenes/forest.toml"), windStrength)),
        frame(scene, width, height),
        camera(frame.startCamera()) {
    camera.aspect = static_cast<double>(width) / height;
  }
  static Scene withWind(Scene scene, std::optional<double> windStrength) {
    if (windStrength) scene.vegetation->wind_strength = *windStrength;
    return scene;
  }
  void step(int v) { stepForestView(camera, *frame.terrain(), v); }
};

struct IdDepthTarget {
  gl::Texture ids, depth;
  gl::Framebuffer framebuffer;
  int width, height;
  IdDepthTarget(int w, int h) : ids(GL_R32UI, w, h), depth(GL_DEPTH_COMPONENT32F, w, h), width(w), height(h) {
    framebuffer.attach(GL_COLOR_ATTACHMENT0, ids);
    framebuffer.attach(GL_DEPTH_ATTACHMENT, depth);
  }
  // Binds, clears IDs to 0 (sky) and depth to 0 (far), sets the engine's depth test and culling.
  void bindAndClear() const {
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer.id());
    glViewport(0, 0, width, height);
    const GLuint zero[4] = {0, 0, 0, 0};
    glClearBufferuiv(GL_COLOR, 0, zero);
    glClearDepth(0.0);
    glClear(GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_GREATER);
    glEnable(GL_CULL_FACE);
    glCullFace(GL_BACK);
  }
  // Bottom row first, as OpenGL stores them.
  std::vector<std::uint32_t> readIds() const {
    std::vector<std::uint32_t> p(static_cast<size_t>(width) * height);
    glGetTextureImage(ids.id(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, static_cast<GLsizei>(p.size() * 4), p.data());
    return p;
  }
  std::vector<float> readDepth() const {
    std::vector<float> p(static_cast<size_t>(width) * height);
    glGetTextureImage(depth.id(), 0, GL_DEPTH_COMPONENT, GL_FLOAT, static_cast<GLsizei>(p.size() * 4), p.data());
    return p;
  }
};

}  // namespace forest::test
