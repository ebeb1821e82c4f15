// The eye-space blur of the shadow term (thesis §6.3, §9.4.2; render/src/blur_pass): off it is the
// term itself, its width shrinks with depth, and it does not leak across depth discontinuities; at
// half resolution it equals the full one away from edges, and keeps an object's terminator apart
// but not the terrain's.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "forest/core/error.hpp"
#include "forest/core/scene.hpp"
#include "forest/render/frame.hpp"
#include "forest/terrain/terrain.hpp"
#include "gl_test_support.hpp"
#include "test_paths.hpp"

namespace forest::test {
namespace {

using glm::dvec3;

constexpr int kWidth = 320, kHeight = 240;

Camera cameraAt(dvec3 position, double yawDeg, double pitchDeg, double far) {
  return test::cameraAt(position, yawDeg, pitchDeg, far, static_cast<double>(kWidth) / kHeight);
}

class BlurGl : public GlTest {};

// Eye depth of pixel i from the reversed-Z depth buffer.
double eyeDepthAt(const Camera& c, float depth) { return c.near * c.far / (c.near + depth * (c.far - c.near)); }

// A plane with a box above it, lit from high up, and a view of the box's shadow on the plane.
Scene boxOverPlane() {
  Scene scene;
  scene.sun.direction = glm::normalize(dvec3(0.3, -1.0, 0.2));
  scene.props.push_back({dvec3(-40, -1, -80), dvec3(40, 0, 40), dvec3(0.6)});
  scene.props.push_back({dvec3(-2, 3, -2), dvec3(2, 5, 2), dvec3(0.8)});
  return scene;
}
Camera boxOverPlaneView() { return cameraAt({0, 6, 14}, 0.0, -20.0, 300.0); }

// The blur off, the lighting pass looks the term up itself (no shadow-term pass runs): what it
// used must equal, texel for texel, the term the shadow-term pass writes for the blur when the
// blur is on — the same lookup on the same G-buffer and map.
TEST_F(BlurGl, BlurOffLightsWithTheTermThePassWouldWrite) {
  const Scene scene = boxOverPlane();  // the frame keeps a reference
  render::Frame frame(scene, kWidth, kHeight);
  const Camera camera = boxOverPlaneView();
  for (const int pcf : {0, 2}) {
    render::FrameSettings settings;
    settings.pcfRadius = pcf;
    settings.blurRadius = 0.0;
    frame.resetHistory();
    frame.render(camera, 0.0, settings);
    const std::vector<float> inLighting = frame.readShadowTerm();
    EXPECT_EQ(frame.readBlurredShadowTerm(), inLighting);
    settings.blurRadius = 4.0;
    frame.resetHistory();
    frame.render(camera, 0.0, settings);
    const std::vector<float> fromPass = frame.readShadowTerm();
    EXPECT_EQ(inLighting, fromPass) << "pcf " << pcf;
    // Not a trivial image: the box shadows part of the plane, and most of it is lit.
    const auto shadowed = std::count_if(fromPass.begin(), fromPass.end(), [](float t) { return t < 0.5f; });
    EXPECT_GT(shadowed, static_cast<long>(fromPass.size() / 100)) << "pcf " << pcf;
    EXPECT_LT(shadowed, static_cast<long>(fromPass.size() / 2)) << "pcf " << pcf;
  }
}

// FrameSettings::keepShadowTerm off (the walkthrough's runs) leaves the term's target out of the
// lighting pass: the image is the same, pixel for pixel, and reading the term it did not keep is
// an error, not stale data; with the blur on, the term pass's own output can still be read.
TEST_F(BlurGl, AFrameThatKeepsNoTermDrawsTheSameImageAndRefusesToReadIt) {
  const Scene scene = boxOverPlane();  // the frame keeps a reference
  render::Frame frame(scene, kWidth, kHeight);
  const Camera camera = boxOverPlaneView();
  for (const double blur : {0.0, 4.0}) {
    render::FrameSettings settings;
    settings.blurRadius = blur;
    frame.render(camera, 0.0, settings);
    const Image8 kept = frame.readColor();
    const std::vector<float> term = frame.readShadowTerm();
    settings.keepShadowTerm = false;
    frame.render(camera, 0.0, settings);
    EXPECT_EQ(frame.readColor().pixels, kept.pixels) << "blur " << blur;
    EXPECT_THROW(frame.readBlurredShadowTerm(), Error) << "blur " << blur;
    if (blur > 0.0) EXPECT_EQ(frame.readShadowTerm(), term);
    else EXPECT_THROW(frame.readShadowTerm(), Error);
  }
  EXPECT_EQ(gl::debugErrorCount(), 0u);
}

TEST_F(BlurGl, BlurWidensNearShadowEdgesMoreThanFarOnes) {
  // Two boxes on stilts shadow a plane, one 10 m from the eye and one 60 m; blur 8 px up to 5 m,
  // shrinking as 1/z: about 4 px near, under 1 px far.
  Scene scene;
  scene.sun.direction = glm::normalize(dvec3(0.3, -1.0, 0.2));
  scene.props.push_back({dvec3(-60, -1, -120), dvec3(60, 0, 40), dvec3(0.6)});
  scene.props.push_back({dvec3(-1.5, 2, -1.5), dvec3(1.5, 2.5, 1.5), dvec3(0.8)});    // near caster
  scene.props.push_back({dvec3(-6, 8, -56), dvec3(6, 9, -44), dvec3(0.8)});          // far caster
  render::Frame frame(scene, kWidth, kHeight);
  const Camera camera = cameraAt({0, 5, 8}, 0.0, -12.0, 300.0);
  render::FrameSettings settings;
  settings.method = shadows::ShadowMethod::Uniform;
  settings.blurRadius = 8.0;
  settings.blurReferenceDepth = 5.0;
  frame.render(camera, 0.0, settings);
  const std::vector<float> term = frame.readShadowTerm(), blurred = frame.readBlurredShadowTerm(), depth = frame.readDepth();
  const std::vector<std::uint32_t> ids = frame.readObjectIds();
  const std::uint32_t plane = frame.objects().propIdBase();
  // Per region: soft pixels (0.02 < blurred < 0.98) per edge pixel of the unblurred term (a pixel
  // whose right or upper neighbour differs by more than 0.5): the soft band's width in pixels.
  int soft[2] = {0, 0}, edges[2] = {0, 0};
  for (int y = 0; y + 1 < kHeight; ++y)
    for (int x = 0; x + 1 < kWidth; ++x) {
      const size_t i = static_cast<size_t>(y) * kWidth + x;
      if (ids[i] != plane) continue;
      const double z = eyeDepthAt(camera, depth[i]);
      const int region = z < 20.0 ? 0 : (z > 45.0 && z < 80.0 ? 1 : -1);
      if (region < 0) continue;
      soft[region] += blurred[i] > 0.02f && blurred[i] < 0.98f ? 1 : 0;
      edges[region] += std::abs(term[i] - term[i + 1]) > 0.5f || std::abs(term[i] - term[i + kWidth]) > 0.5f ? 1 : 0;
    }
  std::printf("[blur] near: %d soft pixels over %d edge pixels; far: %d over %d\n", soft[0], edges[0], soft[1], edges[1]);
  ASSERT_GT(edges[0], 10);
  ASSERT_GT(edges[1], 10);
  const double widthNear = static_cast<double>(soft[0]) / edges[0], widthFar = static_cast<double>(soft[1]) / edges[1];
  EXPECT_GT(widthNear, 2.0 * widthFar) << widthNear << " vs " << widthFar;
}

TEST_F(BlurGl, BlurDoesNotLeakAcrossADepthDiscontinuity) {
  // A lit box face right in front of a shadowed stretch of plane 25–40 m behind it.
  Scene scene;
  scene.sun.direction = glm::normalize(dvec3(0.2, -1.0, -0.6));  // from behind the camera
  scene.props.push_back({dvec3(-60, -1, -120), dvec3(60, 0, 20), dvec3(0.6)});      // plane
  scene.props.push_back({dvec3(-1, 0, -6), dvec3(1, 3, -5), dvec3(0.8)});           // lit box in view
  scene.props.push_back({dvec3(-12, 12, -34), dvec3(12, 13, -14), dvec3(0.8)});     // shadows the plane behind
  render::Frame frame(scene, kWidth, kHeight);
  const Camera camera = cameraAt({0, 2.5, 2}, 0.0, -5.0, 300.0);
  for (const int scale : {1, 2}) {  // at half resolution the upsample must not leak either
  render::FrameSettings settings;
  settings.blurRadius = 8.0;
  settings.blurReferenceDepth = 40.0;  // full radius everywhere in view
  settings.shadowTermScale = scale;
  frame.render(camera, 0.0, settings);
  const std::vector<float> term = frame.readShadowTerm(), blurred = frame.readBlurredShadowTerm(), depth = frame.readDepth();
  const std::vector<std::uint32_t> ids = frame.readObjectIds();
  const std::uint32_t box = frame.objects().propIdBase() + 1;
  // Lit box pixels with a shadowed pixel at least twice as deep within the kernel's reach and no
  // shadow at their own depth (the box's own shadow beside its foot may be blurred in, rightly).
  int checked = 0, leaked = 0;
  for (int y = 8; y < kHeight - 8; ++y)
    for (int x = 8; x < kWidth - 8; ++x) {
      const size_t i = static_cast<size_t>(y) * kWidth + x;
      if (ids[i] != box || term[i] < 0.99f) continue;
      const double z = eyeDepthAt(camera, depth[i]);
      bool farShadow = false, nearShadow = false;
      for (int dy = -8; dy <= 8; ++dy)
        for (int dx = -8; dx <= 8; ++dx) {
          const size_t j = static_cast<size_t>(y + dy) * kWidth + (x + dx);
          if (ids[j] == 0 || term[j] >= 0.99f) continue;
          const double zj = eyeDepthAt(camera, depth[j]);
          if (zj > 2.0 * z && term[j] < 0.5f && (dx == 0 || dy == 0)) farShadow = true;
          if (std::abs(zj - z) <= 0.1 * z) nearShadow = true;
        }
      if (!farShadow || nearShadow) continue;
      ++checked;
      leaked += blurred[i] < term[i] - 1e-3f ? 1 : 0;
    }
  std::printf("[blur] term scale %d: %d lit box pixels beside a shadow, %d darkened by the blur\n", scale, checked, leaked);
  EXPECT_GT(checked, 20) << "scale " << scale;
  EXPECT_EQ(leaked, 0) << "scale " << scale;
  }
}

// The term at half resolution (FrameSettings::shadowTermScale 2: a lookup per 2 × 2 block at its
// nearest surface, the blur on the blocks, a depth-aware upsample in the lighting) against the full
// resolution one, on the box's shadow on the plane, blur 3 px up to 40 m — the whole plane in view,
// and nearer than the depth where the radius falls to 2 px (60 m), within which lighting upsamples
// the half-resolution term (σ = 1.5 px; at half resolution σ_s = sqrt(1.5² − 3/6) / 2 = 0.66 texel,
// cut at 3σ: 1 tap each side).
// (1) Away from every edge they are equal: a pixel's half-resolution term reads texels at most one
// upsample texel and one blur tap from its block — within b = 2 · (1 + 1) + 1 = 5 pixels — and the
// full one reads 3 taps; where the unblurred full term is one value over that window, on one surface
// (the same object, depth within the blur's 5%), both are that value.
// (2) Near the shadow's edge the half term's lookups stand at pixel centres of its blocks and the
// blur and the upsample weigh them symmetrically about the pixel, so the term's 0.5 crossing moves
// by less than a pixel: every pixel with no change of the full term's state within 1 pixel keeps
// its state.
TEST_F(BlurGl, HalfResolutionTermEqualsTheFullOneAwayFromEdgesAndKeepsItsEdges) {
  const Scene scene = boxOverPlane();  // the frame keeps a reference
  render::Frame frame(scene, kWidth, kHeight);
  const Camera camera = boxOverPlaneView();
  render::FrameSettings settings;
  settings.blurRadius = 3.0;
  settings.blurReferenceDepth = 40.0;
  frame.render(camera, 0.0, settings);
  const std::vector<float> unblurred = frame.readShadowTerm(), full = frame.readBlurredShadowTerm(), depth = frame.readDepth();
  const std::vector<std::uint32_t> ids = frame.readObjectIds();
  settings.shadowTermScale = 2;
  frame.render(camera, 0.0, settings);
  const std::vector<float> half = frame.readBlurredShadowTerm();
  ASSERT_EQ(half.size(), full.size());
  EXPECT_NE(half, full);  // the half-resolution path ran: its edges differ somewhere
  auto at = [](int x, int y) { return static_cast<size_t>(y) * kWidth + x; };
  // Within `b` of (x, y): one surface, and the unblurred term one value (`uniformTerm`) or one state.
  auto windowIs = [&](int x, int y, int b, bool uniformTerm) {
    const size_t i = at(x, y);
    const double z = eyeDepthAt(camera, depth[i]);
    for (int dy = -b; dy <= b; ++dy)
      for (int dx = -b; dx <= b; ++dx) {
        const size_t j = at(x + dx, y + dy);
        if (ids[j] != ids[i] || std::abs(eyeDepthAt(camera, depth[j]) - z) > 0.05 * z) return false;
        if (uniformTerm ? unblurred[j] != unblurred[i] : (full[j] < 0.5f) != (full[i] < 0.5f)) return false;
      }
    return true;
  };
  int equal[2] = {0, 0}, unequal = 0, nearEdge = 0, flipped = 0;
  for (int y = 8; y < kHeight - 8; ++y)
    for (int x = 8; x < kWidth - 8; ++x) {
      const size_t i = at(x, y);
      if (ids[i] == 0) continue;
      if (windowIs(x, y, 5, true)) {
        ++equal[unblurred[i] < 0.5f ? 0 : 1];
        unequal += std::abs(half[i] - full[i]) > 1e-3f ? 1 : 0;
      } else if (windowIs(x, y, 1, false) && !windowIs(x, y, 5, false)) {  // on one surface, 1-5 px from an edge
        ++nearEdge;
        flipped += (half[i] < 0.5f) != (full[i] < 0.5f) ? 1 : 0;
      }
    }
  std::printf("[half term] %d shadowed and %d lit pixels away from edges, %d differ; %d pixels 1-5 px from an edge, %d flipped\n",
              equal[0], equal[1], unequal, nearEdge, flipped);
  EXPECT_GT(equal[0], 500);
  EXPECT_GT(equal[1], 500);
  EXPECT_EQ(unequal, 0);
  EXPECT_GT(nearEdge, 100);
  EXPECT_EQ(flipped, 0);
  EXPECT_EQ(gl::debugErrorCount(), 0u);
}

// Beyond the eye depth where the blur's radius falls to 2 px (R · z_ref / 2: 15 m for 3 px up to
// 10 m) the half-resolution term would lose the map's detail, so the lighting looks the term up
// there: the term it used equals, pixel for pixel, the term of the same frame with the blur off
// (the same lookup); nearer, it is the upsampled one, which differs at the shadow's edges.
TEST_F(BlurGl, BeyondTheHalfTermDepthLightingLooksTheTermUp) {
  const Scene scene = boxOverPlane();  // the frame keeps a reference
  render::Frame frame(scene, kWidth, kHeight);
  const Camera camera = cameraAt({0, 3, 17}, 0.0, -8.0, 300.0);  // the plane from ~7 m to 97 m, the box's shadow across 15 m
  render::FrameSettings settings;
  frame.render(camera, 0.0, settings);  // blur off
  const std::vector<float> lookedUp = frame.readBlurredShadowTerm(), depth = frame.readDepth();
  settings.blurRadius = 3.0;
  settings.shadowTermScale = 2;
  frame.render(camera, 0.0, settings);
  const std::vector<float> used = frame.readBlurredShadowTerm();
  const double split = 0.5 * settings.blurRadius * settings.blurReferenceDepth;
  int beyond = 0, beyondDiffer = 0, nearer = 0, nearerDiffer = 0, nearerEdges = 0;
  for (size_t i = 0; i < depth.size(); ++i) {
    if (depth[i] == 0.0f) continue;  // sky
    const double z = eyeDepthAt(camera, depth[i]);
    if (z > split * 1.001) {  // the float depth test's rounding
      ++beyond;
      beyondDiffer += used[i] != lookedUp[i] ? 1 : 0;
    } else if (z < split * 0.999) {
      ++nearer;
      nearerDiffer += used[i] != lookedUp[i] ? 1 : 0;
      nearerEdges += lookedUp[i] > 0.0f && lookedUp[i] < 1.0f ? 1 : 0;
    }
  }
  std::printf("[half term depth] %d pixels beyond %.0f m, %d differ from the lookup; %d nearer, %d differ\n", beyond, split, beyondDiffer,
              nearer, nearerDiffer);
  EXPECT_GT(beyond, 1000);
  EXPECT_EQ(beyondDiffer, 0);
  ASSERT_GT(nearer, 1000);
  EXPECT_GT(nearerDiffer, 0);  // the upsample's blurred edges (and its shadowed pixels are the box's)
  EXPECT_EQ(gl::debugErrorCount(), 0u);
}

// A terminator at half resolution (shaders/shadow_term.frag, term_upsample.frag). Per pixel, the
// CPU says which side of a terminator it lies on: `Side::Lit` faces the sun, `Side::Averted` faces
// away (the term is 0 there by fiat), `Side::Unknown` is neither or undecided.
enum class Side { Unknown, Lit, Averted };

// Pixel p's upsample texels (term_upsample.frag): the 2 × 2 term texels whose centres surround it,
// q = (p + 0.5) / 2 − 0.5, texels floor(q) + {0, 1}²; texel t stands for pixels 2t + {0, 1}².
std::vector<glm::ivec2> upsampleTexels(int x, int y) {
  const glm::ivec2 base(static_cast<int>(std::floor((x + 0.5) * 0.5 - 0.5)), static_cast<int>(std::floor((y + 0.5) * 0.5 - 0.5)));
  return {base, base + glm::ivec2(1, 0), base + glm::ivec2(0, 1), base + glm::ivec2(1, 1)};
}

struct TerminatorPixels {
  int besideAverted = 0;  // lit pixels with an all-averted texel among their upsample texels
  int fullDarkened = 0;   // … whose full-resolution blurred term is below 1
  int halfDarkened = 0;   // … whose half-resolution one is
  int clear = 0;          // … with no shadow from the map near: unblurred 1 at every pixel within 5 px but the averted ones
  int clearHalfDarkened = 0;
};

// Over the lit pixels (`side`) with an upsample texel whose block is all averted and within 4% of
// the pixel's depth (the blur's and the upsample's tolerance is 5%): how many the full and the half
// resolution terms darken. The full blur (3 taps each way) reaches the block (within 2 px) and
// mixes its 0 in with a positive weight: below 1. The half one takes the block's texel — whose own
// term is 0, so below 1 after its blur — with a positive weight, unless its depth is stored negated
// to keep the sides apart: then, where the map casts no shadow near, its lit texels' 1.
TerminatorPixels termBesideTerminators(const std::vector<Side>& side, const std::vector<double>& z, const std::vector<float>& unblurred,
                                       const std::vector<float>& full, const std::vector<float>& half) {
  auto at = [](int x, int y) { return static_cast<size_t>(y) * kWidth + x; };
  auto blockAverted = [&](glm::ivec2 t, double zPixel) {
    for (int dy = 0; dy <= 1; ++dy)
      for (int dx = 0; dx <= 1; ++dx) {
        const size_t j = at(2 * t.x + dx, 2 * t.y + dy);
        if (side[j] != Side::Averted || std::abs(z[j] - zPixel) > 0.04 * zPixel) return false;
      }
    return true;
  };
  TerminatorPixels r;
  for (int y = 8; y < kHeight - 8; ++y)
    for (int x = 8; x < kWidth - 8; ++x) {
      const size_t i = at(x, y);
      if (side[i] != Side::Lit) continue;
      bool besideAverted = false, shadowNear = false;
      for (const glm::ivec2 t : upsampleTexels(x, y)) besideAverted = besideAverted || blockAverted(t, z[i]);
      if (!besideAverted) continue;
      for (int dy = -5; dy <= 5; ++dy)
        for (int dx = -5; dx <= 5; ++dx) shadowNear = shadowNear || (side[at(x + dx, y + dy)] != Side::Averted && unblurred[at(x + dx, y + dy)] < 1.0f);
      ++r.besideAverted;
      r.fullDarkened += full[i] < 1.0f ? 1 : 0;
      r.halfDarkened += half[i] < 1.0f ? 1 : 0;
      r.clear += shadowNear ? 0 : 1;
      r.clearHalfDarkened += !shadowNear && half[i] < 1.0f ? 1 : 0;
    }
  return r;
}

// The unblurred term and the full and half resolution blurred terms of one view, blur 3 px up to
// `referenceDepth`, and each pixel's eye depth.
struct ThreeTerms {
  std::vector<float> unblurred, full, half, depth;  // depth: reversed-Z, 0 for the sky
  std::vector<double> z;
};
ThreeTerms threeTerms(render::Frame& frame, const Camera& camera, double referenceDepth) {
  render::FrameSettings settings;
  settings.culling = culling::CullingStrategy::Frustum;
  settings.blurRadius = 3.0;
  settings.blurReferenceDepth = referenceDepth;
  ThreeTerms t;
  frame.render(camera, 0.0, settings);
  t.unblurred = frame.readShadowTerm();
  t.full = frame.readBlurredShadowTerm();
  t.depth = frame.readDepth();
  for (const float d : t.depth) t.z.push_back(d == 0.0f ? 0.0 : eyeDepthAt(camera, d));
  settings.shadowTermScale = 2;
  frame.render(camera, 0.0, settings);
  t.half = frame.readBlurredShadowTerm();
  return t;
}

// On an object (a prop, a crown's leaves) the half-resolution term keeps a terminator's two sides
// apart: a lit face beside an averted one keeps its light, where the full-resolution blur mixes the
// averted face's 0 in. A box lit from (1, 0.6, 0.4): its averted −x face and lit +z face, which
// face a pixel shows decided on the CPU from its position.
TEST_F(BlurGl, HalfResolutionKeepsAnObjectsTerminatorApart) {
  Scene scene;
  scene.sun.direction = glm::normalize(dvec3(-1.0, -0.6, -0.4));
  scene.props.push_back({dvec3(-40, -1, -40), dvec3(40, 0, 40), dvec3(0.6)});
  scene.props.push_back({dvec3(-2, 0, -2), dvec3(2, 4, 2), dvec3(0.8)});
  render::Frame frame(scene, kWidth, kHeight);
  const Camera camera = cameraAt({-6, 3, 6}, glm::degrees(std::atan2(-6.0, 6.0)), glm::degrees(std::atan2(-1.0, std::hypot(6.0, 6.0))), 200.0);
  const ThreeTerms t = threeTerms(frame, camera, 40.0);  // the box within 60 m: upsampled
  const std::vector<float>& depth = t.depth;
  std::vector<Side> side(depth.size(), Side::Unknown);
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      const size_t i = static_cast<size_t>(y) * kWidth + x;
      if (depth[i] == 0.0f) continue;
      const dvec3 p = pixelPosition(camera, x, y, depth[i], kWidth, kHeight);
      if (p.y < 0.05 || p.y > 3.95) continue;
      if (std::abs(p.x + 2.0) < 0.01 && std::abs(p.z) < 1.99) side[i] = Side::Averted;
      if (std::abs(p.z - 2.0) < 0.01 && std::abs(p.x) < 1.99) side[i] = Side::Lit;
    }
  const TerminatorPixels r = termBesideTerminators(side, t.z, t.unblurred, t.full, t.half);
  std::printf("[terminator] box: %d lit pixels beside the averted face, darkened at full resolution %d; %d with no shadow near, darkened at half %d\n",
              r.besideAverted, r.fullDarkened, r.clear, r.clearHalfDarkened);
  EXPECT_GT(r.clear, 20);
  EXPECT_EQ(r.fullDarkened, r.besideAverted);
  EXPECT_EQ(r.clearHalfDarkened, 0);
  EXPECT_EQ(gl::debugErrorCount(), 0u);
}

// On the terrain the half-resolution term takes the averted side's 0 into the lit side beside a
// terminator as the full-resolution blur does (keeping the sides apart there lit pixels the
// ray-traced truth shadows: docs/experiments.md). The default terrain at full resolution (the CPU
// heightfield is the drawn one) under a sun 8° up; which way a pixel's drawn triangle faces is
// decided on the CPU from the heightfield's slopes at its position (undecided within 5 cm of a
// triangle's edge, where one-sided slopes differ, or within 0.02 of grazing).
TEST_F(BlurGl, HalfResolutionBlursTheTerrainsTerminatorAsFullResolutionDoes) {
  Scene scene = loadScene(std::string(FOREST_REPO_DATA) + "/scenes/terrain.toml");
  scene.terrain->lod_error_pixels = 0.01;
  const double elevation = glm::radians(8.0);
  scene.sun.direction = {-std::cos(elevation) * 0.6, -std::sin(elevation), -std::cos(elevation) * 0.8};
  render::Frame frame(scene, kWidth, kHeight);
  const terrain::Terrain& terrain = *frame.terrain();
  const dvec3 toSun = -scene.sun.direction;
  auto sideAt = [&](const dvec3& p) {
    const double e = 0.05, h = terrain.heightAt(p.x, p.z);
    const double xPlus = terrain.heightAt(p.x + e, p.z) - h, xMinus = h - terrain.heightAt(p.x - e, p.z);
    const double zPlus = terrain.heightAt(p.x, p.z + e) - h, zMinus = h - terrain.heightAt(p.x, p.z - e);
    if (std::abs(xPlus - xMinus) > 1e-6 || std::abs(zPlus - zMinus) > 1e-6) return Side::Unknown;
    const double facing = glm::dot(glm::normalize(dvec3(-xPlus / e, 1.0, -zPlus / e)), toSun);
    return facing > 0.02 ? Side::Lit : facing < -0.02 ? Side::Averted : Side::Unknown;
  };
  TerminatorPixels total;
  for (int view = 0; view < 6; ++view) {
    Camera camera = cameraAt({-300.0 + 120.0 * view, 0, 200.0 - 80.0 * view}, 60.0 * view, -25.0, 3000.0);
    camera.position.y = terrain.heightAt(camera.position.x, camera.position.z) + 25.0;
    const ThreeTerms t = threeTerms(frame, camera, 200.0);  // within 300 m upsampled
    const std::vector<float>& depth = t.depth;
    std::vector<Side> side(depth.size(), Side::Unknown);
    for (int y = 0; y < kHeight; ++y)
      for (int x = 0; x < kWidth; ++x) {
        const size_t i = static_cast<size_t>(y) * kWidth + x;
        if (depth[i] != 0.0f && t.z[i] < 280.0) side[i] = sideAt(pixelPosition(camera, x, y, depth[i], kWidth, kHeight));
      }
    const TerminatorPixels r = termBesideTerminators(side, t.z, t.unblurred, t.full, t.half);
    total.besideAverted += r.besideAverted;
    total.fullDarkened += r.fullDarkened;
    total.halfDarkened += r.halfDarkened;
  }
  std::printf("[terminator] terrain: %d lit pixels beside averted ones; darkened at full resolution %d, at half %d\n", total.besideAverted,
              total.fullDarkened, total.halfDarkened);
  EXPECT_GT(total.besideAverted, 50);
  EXPECT_EQ(total.fullDarkened, total.besideAverted);
  EXPECT_EQ(total.halfDarkened, total.besideAverted);
  EXPECT_EQ(gl::debugErrorCount(), 0u);
}

}  // namespace
}  // namespace forest::test
