#include "forest/render/frame.hpp"

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <chrono>
#include <optional>

#include "forest/core/error.hpp"
#include "forest/shadows/casters.hpp"
#include "forest/shadows/focus_body.hpp"

namespace forest::render {
namespace {

using Clock = std::chrono::steady_clock;
using glm::dvec3;

// uRays of shaders/fullscreen.vert: A with A·(x_ndc, y_ndc, −1) = the camera-relative direction
// through that pixel scaled to eye depth 1 (the position of a pixel at eye depth z is z times it).
glm::mat3 pixelRays(const Camera& camera) {
  const glm::dmat4 inverse = glm::inverse(camera.projection() * camera.view() * glm::translate(glm::dmat4(1.0), camera.position));
  const dvec3 forward = camera.forward();
  auto ray = [&](double x, double y) {
    const glm::dvec4 h = inverse * glm::dvec4(x, y, 0.5, 1.0);
    const dvec3 p = dvec3(h) / h.w;
    return p / glm::dot(p, forward);
  };
  const dvec3 centre = ray(0.0, 0.0);
  return glm::mat3(glm::dmat3(ray(1.0, 0.0) - centre, ray(0.0, 1.0) - centre, -centre));
}

double millisecondsSince(Clock::time_point start) {
  glFinish();  // per-pass times include the GPU's work
  return 1e3 * std::chrono::duration<double>(Clock::now() - start).count();
}

// Shadow clip z in [−1, 1] → [0, 1] for the engine's zero-to-one clip control (z' = (z + w) / 2).
glm::dmat4 zeroToOneDepth() {
  glm::dmat4 m(1.0);
  m[2][2] = 0.5;
  m[3][2] = 0.5;
  return m;
}

// Winding is decided in the image plane only (x, y), so the test maps a small triangle that faces
// the sun (counter-clockwise seen from it) through the light matrix at the focus body's centre.
bool lightMirrorsWinding(const shadows::ShadowSetup& setup, const dvec3& l) {
  const auto [v, u] = shadows::axesAcrossLight(l);  // u × v = −l: the normal points at the sun
  const Aabb box = setup.body.bounds();
  const dvec3 c = box.centre();
  const double size = std::max(box.diagonal(), 1e-6) * 1e-3;
  auto project = [&](const dvec3& p) {
    const glm::dvec4 h = setup.worldToShadowClip * glm::dvec4(p, 1.0);
    return glm::dvec2(h) / h.w;
  };
  const glm::dvec2 a = project(c), b = project(c + size * u), d = project(c + size * v);
  return (b.x - a.x) * (d.y - a.y) - (b.y - a.y) * (d.x - a.x) < 0.0;
}

// World size of one shadow-map texel at p (the larger of two directions across the light).
double texelWorldSize(const glm::dmat4& worldToShadowClip, int mapSize, const dvec3& p, const dvec3& l) {
  const auto [u, v] = shadows::axesAcrossLight(l);
  auto map = [&](const dvec3& q) {
    const glm::dvec4 h = worldToShadowClip * glm::dvec4(q, 1.0);
    return glm::dvec2(h) / h.w * (0.5 * mapSize);  // texels
  };
  const double step = 1e-3 * std::max(1.0, glm::length(p));
  const double alongU = glm::length(map(p + step * u) - map(p)) / step, alongV = glm::length(map(p + step * v) - map(p)) / step;
  const double texelsPerMetre = std::min(alongU, alongV);
  return texelsPerMetre > 0.0 ? 1.0 / texelsPerMetre : 0.0;
}

// 2×2 PCF reads the texels around the lookup: a receiver needs the casters of a footprint
// kFilterTexels wide around it, so receiver boxes grow by that many texels (their largest size
// over the box's corners) before casters are selected.
constexpr double kFilterTexels = 1.5;

// The blur averages only samples whose eye depth is within this share of the centre's (no bleeding
// across silhouettes; a sloped surface's depth changes less than this over 16 pixels).
constexpr double kBlurDepthTolerance = 0.05;

// z_f for n moves 20% of the way to the new value each frame (§9.2.5: the visible set's z_f jumps
// when objects appear).
constexpr double kFarDepthSmoothing = 0.2;

}  // namespace

FocusBound parseFocusBound(std::string_view name) {
  if (name == "receivers") return FocusBound::Receivers;
  if (name == "frustum") return FocusBound::Frustum;
  throw InputError(fmt::format("focus bound '{}': expected receivers or frustum", name));
}

std::string_view focusBoundName(FocusBound bound) { return bound == FocusBound::Receivers ? "receivers" : "frustum"; }

CasterSelection parseCasterSelection(std::string_view name) {
  if (name == "receivers") return CasterSelection::Receivers;
  if (name == "frustum-body") return CasterSelection::FrustumBody;
  if (name == "all") return CasterSelection::All;
  throw InputError(fmt::format("caster selection '{}': expected receivers, frustum-body or all", name));
}

std::string_view casterSelectionName(CasterSelection selection) {
  switch (selection) {
    case CasterSelection::Receivers: return "receivers";
    case CasterSelection::FrustumBody: return "frustum-body";
    case CasterSelection::All: return "all";
  }
  return "?";
}

// GPU resources of the passes.
struct Frame::Passes {
  // Geometry pass: G-buffer renderers and targets.
  std::unique_ptr<TerrainRenderer> terrainGBuffer, terrainDepth;
  std::unique_ptr<TreeRenderer> treesGBuffer, treesDepth;
  std::unique_ptr<PropRenderer> propsGBuffer, propsDepth;
  // The TSM shadow pass (linear light depth), built the first time a TSM frame needs them.
  std::unique_ptr<TerrainRenderer> terrainLightDepth;
  std::unique_ptr<TreeRenderer> treesLightDepth;
  std::unique_ptr<PropRenderer> propsLightDepth;
  gl::Texture albedo, shadingNormal, geometricNormal, objectId, depth;
  gl::Framebuffer gbuffer;
  // Shadow pass.
  gl::Texture shadowMap;
  gl::Framebuffer shadowFramebuffer;
  int shadowMapSize = 0;
  // Shadow term and lighting.
  gl::Texture shadowTerm, blurTemporary, blurred, color;
  gl::Framebuffer shadowTermFramebuffer, blurTemporaryFramebuffer, colorFramebuffer;  // colour: + the blurred term
  gl::Program shadowTermProgram, blurProgram, lightingProgram;
  gl::VertexArray empty;

  Passes(int width, int height)
      : albedo(GL_RGBA8, width, height),
        shadingNormal(GL_RGBA16F, width, height),
        geometricNormal(GL_RGBA16F, width, height),
        objectId(GL_R32UI, width, height),
        depth(GL_DEPTH_COMPONENT32F, width, height),
        shadowTerm(GL_RG16F, width, height),
        blurTemporary(GL_RG16F, width, height),
        blurred(GL_RG16F, width, height),
        color(GL_RGBA8, width, height),
        shadowTermProgram(gl::loadProgram({"fullscreen.vert", "shadow_term.frag"})),
        blurProgram(gl::loadProgram({"fullscreen.vert", "shadow_blur.frag", "blur_taps.frag"})),
        lightingProgram(gl::loadProgram({"fullscreen.vert", "lighting.frag", "blur_taps.frag"})) {
    gbuffer.attach(GL_COLOR_ATTACHMENT0, albedo);
    gbuffer.attach(GL_COLOR_ATTACHMENT1, shadingNormal);
    gbuffer.attach(GL_COLOR_ATTACHMENT2, geometricNormal);
    gbuffer.attach(GL_COLOR_ATTACHMENT3, objectId);
    gbuffer.attach(GL_DEPTH_ATTACHMENT, depth);
    const GLenum buffers[4] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2, GL_COLOR_ATTACHMENT3};
    glNamedFramebufferDrawBuffers(gbuffer.id(), 4, buffers);
    gbuffer.checkComplete("G-buffer");
    shadowTermFramebuffer.attach(GL_COLOR_ATTACHMENT0, shadowTerm);
    shadowTermFramebuffer.checkComplete("shadow term");
    blurTemporaryFramebuffer.attach(GL_COLOR_ATTACHMENT0, blurTemporary);
    blurTemporaryFramebuffer.checkComplete("blur");
    colorFramebuffer.attach(GL_COLOR_ATTACHMENT0, color);
    colorFramebuffer.attach(GL_COLOR_ATTACHMENT1, blurred);
    const GLenum colorBuffers[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    glNamedFramebufferDrawBuffers(colorFramebuffer.id(), 2, colorBuffers);
    colorFramebuffer.checkComplete("colour");
    for (const gl::Texture* t : {&albedo, &shadingNormal, &geometricNormal, &objectId, &depth, &shadowTerm, &blurTemporary, &blurred}) {
      glTextureParameteri(t->id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
      glTextureParameteri(t->id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    }
  }

  void ensureShadowMap(int size) {
    if (size == shadowMapSize) return;
    shadowMap = gl::Texture(GL_DEPTH_COMPONENT32F, size, size);
    // Hardware 2×2 PCF: linear filtering of depth comparisons.
    glTextureParameteri(shadowMap.id(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTextureParameteri(shadowMap.id(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(shadowMap.id(), GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
    glTextureParameteri(shadowMap.id(), GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
    glTextureParameteri(shadowMap.id(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(shadowMap.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    shadowFramebuffer = gl::Framebuffer();
    shadowFramebuffer.attach(GL_DEPTH_ATTACHMENT, shadowMap);
    glNamedFramebufferDrawBuffer(shadowFramebuffer.id(), GL_NONE);
    shadowFramebuffer.checkComplete("shadow map");
    shadowMapSize = size;
  }
};

Frame::Frame(const Scene& scene, int width, int height) : scene_(scene), width_(width), height_(height) {
  if (width < 1 || height < 1) throw InputError("frame: width and height must be at least 1");
  if (scene.terrain) {
    terrain_ = std::make_unique<terrain::Terrain>(*scene.terrain);
    if (scene.vegetation) forest_ = std::make_unique<vegetation::Forest>(*scene.vegetation, *terrain_);
  }
  objects_ = std::make_unique<SceneObjects>(terrain_.get(), forest_.get(), scene.props);
  passes_ = std::make_unique<Passes>(width, height);
  Passes& p = *passes_;
  if (terrain_) {
    p.terrainGBuffer = std::make_unique<TerrainRenderer>(*terrain_, TerrainRenderer::Output::GBuffer, objects_->terrainIdBase());
    p.terrainDepth = std::make_unique<TerrainRenderer>(*terrain_, TerrainRenderer::Output::ObjectId, objects_->terrainIdBase());
  }
  if (forest_) {
    p.treesGBuffer = std::make_unique<TreeRenderer>(*forest_, SurfaceOutput::GBuffer, objects_->treeIdBase());
    p.treesDepth = std::make_unique<TreeRenderer>(*forest_, SurfaceOutput::ObjectId, objects_->treeIdBase());
  }
  p.propsGBuffer = std::make_unique<PropRenderer>(scene.props, SurfaceOutput::GBuffer, objects_->propIdBase());
  p.propsDepth = std::make_unique<PropRenderer>(scene.props, SurfaceOutput::ObjectId, objects_->propIdBase());
  bvh_ = culling::Bvh(objects_->boxes(), 1);
  culler_.setParameters(scene_.culling);
  for (const Aabb& b : objects_->boxes()) sceneBounds_.extend(b);
}

Frame::~Frame() = default;

void Frame::ensureLightDepthRenderers() {
  Passes& p = *passes_;
  if (p.propsLightDepth) return;
  if (terrain_) p.terrainLightDepth = std::make_unique<TerrainRenderer>(*terrain_, TerrainRenderer::Output::LightDepth, objects_->terrainIdBase());
  if (forest_) p.treesLightDepth = std::make_unique<TreeRenderer>(*forest_, SurfaceOutput::LightDepth, objects_->treeIdBase());
  p.propsLightDepth = std::make_unique<PropRenderer>(scene_.props, SurfaceOutput::LightDepth, objects_->propIdBase());
}

void Frame::moveTrees(std::span<const vegetation::Forest::Move> moves) {
  if (!forest_) throw InputError("moveTrees: the scene has no trees");
  forest_->moveTrees(moves);  // the tree renderers read the forest at every draw
  objectsMoved();
}

void Frame::propsMoved() {
  Passes& p = *passes_;
  for (PropRenderer* r : {p.propsGBuffer.get(), p.propsDepth.get(), p.propsLightDepth.get()})
    if (r) r->update(scene_.props);
  objectsMoved();
}

void Frame::objectsMoved() {
  objects_->updateBoxes(forest_.get(), scene_.props);
  bvh_.refit(objects_->boxes());
  sceneBounds_ = Aabb();
  for (const Aabb& b : objects_->boxes()) sceneBounds_.extend(b);
}

void Frame::resetHistory() {
  culler_.reset();
  smoothedFarDepth_ = -1.0;
  haveVisibleSet_ = false;
}

Camera Frame::startCamera() const {
  Camera c = scene_.startCamera();
  c.aspect = static_cast<double>(width_) / height_;
  if (scene_.camera.above_ground && terrain_)
    c.position.y = terrain_->heightAt(c.position.x, c.position.z) + *scene_.camera.above_ground;
  return c;
}

FrameStats Frame::render(const Camera& camera, double time, const FrameSettings& settings) {
  if (settings.shadowMapSize < 512 || settings.shadowMapSize > 8192)
    throw InputError(fmt::format("shadow map size {}: expected 512 to 8192", settings.shadowMapSize));
  if (settings.pcfRadius < 0 || settings.pcfRadius > 4)
    throw InputError(fmt::format("PCF radius {}: expected 0 to 4", settings.pcfRadius));
  if (!(settings.fogDensity >= 0.0 && settings.fogDensity <= 1.0))
    throw InputError(fmt::format("fog density {}: expected 0 to 1 per metre", settings.fogDensity));
  if (!(settings.blurRadius >= 0.0 && settings.blurRadius <= 16.0))
    throw InputError(fmt::format("blur radius {}: expected 0 to 16 pixels", settings.blurRadius));
  if (!std::isfinite(settings.lookupShiftTexels.x) || !std::isfinite(settings.lookupShiftTexels.y))
    throw InputError("lookup shift: expected finite texels");
  if (!(settings.blurReferenceDepth > 0.0) || !std::isfinite(settings.blurReferenceDepth))
    throw InputError(fmt::format("blur reference depth {}: expected > 0 m", settings.blurReferenceDepth));
  FrameStats stats;
  Passes& p = *passes_;
  const SunSettings& sun = scene_.sun;
  const dvec3 l = glm::normalize(sun.direction);
  stats.sunBelowHorizon = !(l.y < 0.0);  // light travelling upward comes from below the horizon
  const DrawView eye = DrawView::fromCamera(camera, time, sun);
  std::optional<terrain::TerrainLod> lod;
  if (terrain_) lod = terrain_->lodFor(camera, height_);
  const terrain::TerrainLod* eyeLod = lod ? &*lod : nullptr;

  // 1. Geometry pass.
  auto start = Clock::now();
  glBindFramebuffer(GL_FRAMEBUFFER, p.gbuffer.id());
  glViewport(0, 0, width_, height_);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_GREATER);
  glDepthMask(GL_TRUE);
  glEnable(GL_CULL_FACE);
  glCullFace(GL_BACK);
  glDisable(GL_POLYGON_OFFSET_FILL);
  const float zero[4] = {0, 0, 0, 0};
  const GLuint zeroId[4] = {0, 0, 0, 0};
  for (int i = 0; i < 3; ++i) glClearBufferfv(GL_COLOR, i, zero);
  glClearBufferuiv(GL_COLOR, 3, zeroId);
  const float farDepth = 0.0f;
  glClearBufferfv(GL_DEPTH, 0, &farDepth);
  SceneDrawer geometry(*objects_, p.terrainGBuffer.get(), p.treesGBuffer.get(), p.propsGBuffer.get(),
                       eye, eyeLod);
  culling::CullingResult visible;
  if (settings.freezeCulling && haveVisibleSet_) {
    visible.visibleObjects = visibleObjects_;
    visible.stats.trianglesDrawn = geometry.draw(visible.visibleObjects);
    visible.stats.objectsDrawn = static_cast<int>(visible.visibleObjects.size());
    visible.farDepth = culling::farDepthOf(visible.visibleObjects, objects_->boxes(), camera);
  } else {
    visible = culler_.cull(bvh_, objects_->boxes(), camera, settings.culling, geometry);
  }
  haveVisibleSet_ = true;
  stats.geometryMs = millisecondsSince(start);
  stats.culling = visible.stats;
  stats.visibleObjects = static_cast<int>(visible.visibleObjects.size());
  stats.geometryTriangles = visible.stats.trianglesDrawn;
  stats.farDepth = visible.farDepth;

  // 2. Shadow setup from the visible set: V up to z_f, the visible receivers, smoothed z_f for n.
  start = Clock::now();
  smoothedFarDepth_ = smoothedFarDepth_ < 0.0 ? visible.farDepth
                                               : smoothedFarDepth_ + kFarDepthSmoothing * (visible.farDepth - smoothedFarDepth_);
  stats.smoothedFarDepth = smoothedFarDepth_;
  std::vector<Aabb> receivers;
  Aabb receiverBounds;
  for (std::uint32_t o : visible.visibleObjects) {
    receivers.push_back(objects_->boxes()[o]);
    receiverBounds.extend(objects_->boxes()[o]);
  }
  const bool shadowed = !stats.sunBelowHorizon && !receivers.empty() && sceneBounds_.valid();
  std::vector<std::uint32_t> casters;
  if (shadowed) {
    shadows::ShadowInput input;
    input.camera = camera;
    const bool onReceivers = settings.focus == FocusBound::Receivers;
    if (onReceivers) input.camera.far = std::max(visible.farDepth, camera.near * 1.001);
    shadowCamera_ = input.camera;
    input.sunDirection = l;
    input.scene = sceneBounds_;
    if (onReceivers) input.receivers = receiverBounds;
    if (onReceivers && smoothedFarDepth_ > camera.near && smoothedFarDepth_ < input.camera.far) input.nFar = smoothedFarDepth_;
    input.mapSize = settings.shadowMapSize;
    shadowSetup_ = shadows::computeShadowSetup(input, settings.method);
    stats.shadow = shadowSetup_.diagnostics;
    switch (settings.casters) {
      case CasterSelection::Receivers: {
        // Only the part of a receiver inside the view (up to z_f) receives visible shadows: each
        // box is clipped to V first, so a 125 m terrain tile at the edge of the view does not pull
        // in the casters of its unseen part.
        const ConvexBody view = shadows::viewFrustumBody(input.camera);
        std::vector<Aabb> footprints;
        for (const Aabb& receiver : receivers) {
          ConvexBody part = ConvexBody::fromBox(receiver);
          part.clip(view);
          if (!part.empty()) footprints.push_back(part.bounds());
        }
        for (Aabb& box : footprints) {
          double texel = 0.0;
          for (int c = 0; c < 8; ++c)
            texel = std::max(texel, texelWorldSize(shadowSetup_.worldToShadowClip, settings.shadowMapSize, box.corner(c), l));
          box.min -= dvec3(kFilterTexels * texel);
          box.max += dvec3(kFilterTexels * texel);
        }
        const shadows::CasterSelector selector(l, footprints);
        casters = selector.select(objects_->boxes());
        break;
      }
      case CasterSelection::FrustumBody: {
        const ConvexBody body = shadows::computeFocusBody(camera, l, sceneBounds_);
        for (std::uint32_t o = 0; o < objects_->boxes().size(); ++o)
          if (shadows::mayIntersect(body, objects_->boxes()[o])) casters.push_back(o);
        break;
      }
      case CasterSelection::All:
        for (std::uint32_t o = 0; o < objects_->boxes().size(); ++o) casters.push_back(o);
        break;
    }
  }
  stats.casterObjects = static_cast<int>(casters.size());
  visibleObjects_ = visible.visibleObjects;
  casters_ = casters;
  stats.shadowSetupMs = millisecondsSince(start);

  // 3. Shadow pass: casters only, back faces (front faces culled), the eye's LOD.
  start = Clock::now();
  p.ensureShadowMap(settings.shadowMapSize);
  const glm::dmat4 eyeRelativeToShadow =
      zeroToOneDepth() * shadowSetup_.worldToShadowClip * glm::translate(glm::dmat4(1.0), camera.position);
  glBindFramebuffer(GL_FRAMEBUFFER, p.shadowFramebuffer.id());
  glViewport(0, 0, settings.shadowMapSize, settings.shadowMapSize);
  const float nearLight = 1.0f;
  glClearBufferfv(GL_DEPTH, 0, &nearLight);
  if (shadowed && !shadowSetup_.empty) {
    glDepthFunc(GL_LESS);
    // Which faces are "front" for the light: a face turned toward the sun must wind
    // counter-clockwise in the shadow map, unless the light matrix mirrors its image plane.
    glFrontFace(lightMirrorsWinding(shadowSetup_, l) ? GL_CW : GL_CCW);
    glCullFace(settings.backside ? GL_FRONT : GL_BACK);
    if (settings.slopeScaleBias > 0.0) {
      glEnable(GL_POLYGON_OFFSET_FILL);
      glPolygonOffset(static_cast<float>(settings.slopeScaleBias), 0.0f);
    }
    DrawView light = eye;  // the eye's origin and LOD, seen from the light
    light.viewProjectionRelative = eyeRelativeToShadow;
    if (shadowSetup_.linearDepth) {
      // TSM §4: the shaders write the linear light depth (and add the slope bias themselves).
      ensureLightDepthRenderers();
      const glm::dvec4& row = shadowSetup_.worldToLightDepth;
      light.lightDepthRelative = glm::dvec4(dvec3(row), row.w + glm::dot(dvec3(row), camera.position));
      light.depthSlopeBias = settings.slopeScaleBias;
      glDisable(GL_POLYGON_OFFSET_FILL);
      SceneDrawer shadowDrawer(*objects_, p.terrainLightDepth.get(), p.treesLightDepth.get(), p.propsLightDepth.get(), light,
                               eyeLod);
      stats.shadowTriangles = shadowDrawer.draw(casters);
    } else {
      SceneDrawer shadowDrawer(*objects_, p.terrainDepth.get(), p.treesDepth.get(), p.propsDepth.get(), light, eyeLod);
      stats.shadowTriangles = shadowDrawer.draw(casters);
    }
    glDisable(GL_POLYGON_OFFSET_FILL);
    glFrontFace(GL_CCW);
    glCullFace(GL_BACK);
    glDepthFunc(GL_GREATER);
  }
  stats.shadowMs = millisecondsSince(start);

  // 4. Shadow term.
  start = Clock::now();
  const glm::mat3 rays = pixelRays(camera);
  glBindFramebuffer(GL_FRAMEBUFFER, p.shadowTermFramebuffer.id());
  glViewport(0, 0, width_, height_);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  gl::Program& term = p.shadowTermProgram;
  term.set("uDepth", 0);
  term.set("uGeometricNormal", 1);
  term.set("uShadowMap", 3);
  term.set("uRays", rays);
  glm::dmat4 lookup = eyeRelativeToShadow;
  if (settings.lookupShiftTexels != glm::dvec2(0.0)) {
    glm::dmat4 shift(1.0);  // clip x, y += 2·shift/size · w
    shift[3][0] = 2.0 * settings.lookupShiftTexels.x / settings.shadowMapSize;
    shift[3][1] = 2.0 * settings.lookupShiftTexels.y / settings.shadowMapSize;
    lookup = shift * lookup;
  }
  term.set("uEyeRelativeToShadow", glm::mat4(lookup));
  term.set("uLinearDepth", shadowSetup_.linearDepth ? 1 : 0);
  term.set("uEyeRelativeLightDepth", shadowSetup_.eyeRelativeToLightDepthF);
  term.set("uToSun", glm::vec3(-l));
  term.set("uSunUp", shadowed ? 1 : 0);
  term.set("uPcfRadius", settings.pcfRadius);
  term.set("uNear", static_cast<float>(camera.near));
  term.set("uFar", static_cast<float>(camera.far));
  glBindTextureUnit(0, p.depth.id());
  glBindTextureUnit(1, p.geometricNormal.id());
  glBindTextureUnit(3, p.shadowMap.id());
  term.use();
  glBindVertexArray(p.empty.id());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  stats.shadowTermMs = millisecondsSince(start);

  // 4b. Eye-space blur: the horizontal pass here, the vertical one inside lighting (off: lighting
  // reads the term itself).
  start = Clock::now();
  const bool blurOn = settings.blurRadius > 0.0;
  for (gl::Program* program : {&p.blurProgram, &p.lightingProgram}) {
    program->set("uRadius", static_cast<float>(settings.blurRadius));
    program->set("uReferenceDepth", static_cast<float>(settings.blurReferenceDepth));
    program->set("uDepthTolerance", static_cast<float>(kBlurDepthTolerance));
  }
  if (blurOn) {
    gl::Program& blur = p.blurProgram;
    blur.set("uShadowTerm", 0);
    blur.use();
    glBindFramebuffer(GL_FRAMEBUFFER, p.blurTemporaryFramebuffer.id());
    glBindTextureUnit(0, p.shadowTerm.id());
    glDrawArrays(GL_TRIANGLES, 0, 3);
  }
  const gl::Texture* termForLighting = blurOn ? &p.blurTemporary : &p.shadowTerm;
  stats.blurMs = millisecondsSince(start);

  // 5. Lighting.
  start = Clock::now();
  glBindFramebuffer(GL_FRAMEBUFFER, p.colorFramebuffer.id());
  gl::Program& lighting = p.lightingProgram;
  lighting.set("uAlbedo", 0);
  lighting.set("uShadingNormal", 1);
  lighting.set("uShadowTerm", 4);
  lighting.set("uBlurVertical", blurOn ? 1 : 0);
  lighting.set("uRays", rays);
  lighting.set("uToSun", glm::vec3(-l));
  lighting.set("uSunColor", glm::vec3(sun.color));
  lighting.set("uAmbient", static_cast<float>(sun.ambient));
  lighting.set("uSky", glm::vec3(scene_.render.sky_color));
  lighting.set("uSunUp", stats.sunBelowHorizon ? 0 : 1);
  lighting.set("uFogDensity", static_cast<float>(settings.fogDensity));
  glBindTextureUnit(0, p.albedo.id());
  glBindTextureUnit(1, p.shadingNormal.id());
  glBindTextureUnit(4, termForLighting->id());
  lighting.use();
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  for (GLuint unit = 0; unit < 5; ++unit) glBindTextureUnit(unit, 0);
  glEnable(GL_DEPTH_TEST);
  glEnable(GL_CULL_FACE);
  stats.lightingMs = millisecondsSince(start);
  return stats;
}

void Frame::presentTo(GLuint framebuffer, int width, int height) const {
  glBlitNamedFramebuffer(passes_->colorFramebuffer.id(), framebuffer, 0, 0, width_, height_, 0, 0, width, height,
                         GL_COLOR_BUFFER_BIT, GL_LINEAR);
}

Image8 Frame::readColor() const {
  Image8 image(width_, height_, 4);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glGetTextureImage(passes_->color.id(), 0, GL_RGBA, GL_UNSIGNED_BYTE, static_cast<GLsizei>(image.pixels.size()),
                    image.pixels.data());
  flipRows(image);
  return image;
}

std::vector<float> Frame::readShadowTerm() const {
  std::vector<float> v(static_cast<size_t>(width_) * height_);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glGetTextureImage(passes_->shadowTerm.id(), 0, GL_RED, GL_FLOAT, static_cast<GLsizei>(v.size() * 4), v.data());
  return v;
}

std::vector<float> Frame::readBlurredShadowTerm() const {
  std::vector<float> v(static_cast<size_t>(width_) * height_);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glGetTextureImage(passes_->blurred.id(), 0, GL_RED, GL_FLOAT, static_cast<GLsizei>(v.size() * 4), v.data());
  return v;
}

std::vector<std::uint32_t> Frame::readObjectIds() const {
  std::vector<std::uint32_t> v(static_cast<size_t>(width_) * height_);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glGetTextureImage(passes_->objectId.id(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, static_cast<GLsizei>(v.size() * 4), v.data());
  return v;
}

int Frame::shadowMapSize() const { return passes_->shadowMapSize; }

std::vector<float> Frame::readShadowMap() const {
  const int size = passes_->shadowMapSize;
  std::vector<float> v(static_cast<size_t>(size) * size);
  if (size == 0) return v;
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glGetTextureImage(passes_->shadowMap.id(), 0, GL_DEPTH_COMPONENT, GL_FLOAT, static_cast<GLsizei>(v.size() * 4), v.data());
  return v;
}

std::vector<float> Frame::readDepth() const {
  std::vector<float> v(static_cast<size_t>(width_) * height_);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glGetTextureImage(passes_->depth.id(), 0, GL_DEPTH_COMPONENT, GL_FLOAT, static_cast<GLsizei>(v.size() * 4), v.data());
  return v;
}

}  // namespace forest::render
