#include "forest/render/frame.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <optional>

#include "blur_pass.hpp"
#include "forest/core/error.hpp"
#include "forest/core/heap.hpp"
#include "frame_history.hpp"
#include "frame_uniforms.hpp"
#include "forest/render/impostor_atlas.hpp"
#include "geometry_pass.hpp"
#include "lighting_pass.hpp"
#include "pass_floors.hpp"
#include "nearest_depth_pass.hpp"
#include "receiver_pixels.hpp"
#include "shadow_pass.hpp"
#include "shadow_setup_pass.hpp"
#include "shadow_term_pass.hpp"

namespace forest::render {
namespace {

using glm::dvec3;

void validate(const FrameSettings& settings) {
  if (settings.shadowMapSize < 512 || settings.shadowMapSize > 8192)
    throw InputError(fmt::format("shadow map size {}: expected 512 to 8192", settings.shadowMapSize));
  if (settings.pcfRadius < 0 || settings.pcfRadius > 4)
    throw InputError(fmt::format("PCF radius {}: expected 0 to 4", settings.pcfRadius));
  if (settings.fogDensity && !(*settings.fogDensity >= 0.0 && *settings.fogDensity <= 1.0))
    throw InputError(fmt::format("fog density {}: expected 0 to 1 per metre", *settings.fogDensity));
  if (!(settings.blurRadius >= 0.0 && settings.blurRadius <= 16.0))
    throw InputError(fmt::format("blur radius {}: expected 0 to 16 pixels", settings.blurRadius));
  if (!std::isfinite(settings.lookupShiftTexels.x) || !std::isfinite(settings.lookupShiftTexels.y))
    throw InputError("lookup shift: expected finite texels");
  if (settings.shadowTermScale != 1 && settings.shadowTermScale != 2)
    throw InputError(fmt::format("shadow term scale {}: expected 1 (full resolution) or 2 (half)", settings.shadowTermScale));
  if (!(settings.blurReferenceDepth > 0.0) || !std::isfinite(settings.blurReferenceDepth))
    throw InputError(fmt::format("blur reference depth {}: expected > 0 m", settings.blurReferenceDepth));
  if (settings.cascades && (*settings.cascades < 1 || *settings.cascades > shadows::kMaxCascades))
    throw InputError(fmt::format("cascades {}: expected 1 to {}", *settings.cascades, shadows::kMaxCascades));
  if (settings.splitLambda && !(*settings.splitLambda >= 0.0 && *settings.splitLambda <= 1.0))
    throw InputError(fmt::format("split lambda {}: expected 0 to 1", *settings.splitLambda));
  if (settings.cascadeBlend && !(*settings.cascadeBlend >= 0.0 && *settings.cascadeBlend <= 0.5))
    throw InputError(fmt::format("cascade blend {}: expected 0 to 0.5", *settings.cascadeBlend));
  if (!(settings.farSliceScale >= 0.5 && settings.farSliceScale <= 2.0))
    throw InputError(fmt::format("far slice scale {}: expected 0.5 to 2 (1: layers of one size)", settings.farSliceScale));
  if (const int far = sliceMapSize(settings, 1, 2); far < 256 || far > 8192)
    throw InputError(fmt::format("far slice scale {} of {} texels: the far layer's {} texels per side are outside 256 to 8192",
                                 settings.farSliceScale, settings.shadowMapSize, far));
  if (!(settings.impostorDistance == kImpostorDistanceAuto || (settings.impostorDistance >= 0.0 && settings.impostorDistance <= 1e6)))
    throw InputError(fmt::format("impostor distance {}: expected 0 (meshes only) to 1000000 m, or auto", settings.impostorDistance));
  if (!(settings.impostorBand >= 0.0 && settings.impostorBand <= 1.0))
    throw InputError(fmt::format("impostor band {}: expected 0 to 1 (a share of the impostor distance)", settings.impostorBand));
  if (settings.impostorDistance != 0.0 && settings.cacheSlices)
    throw InputError("impostors with cached slices: a layer's cache does not follow a tree's cross-fade (turn one off)");
  if (settings.farSliceScale != 1.0 && settings.casters == CasterSelection::ReceiverMaskGpu)
    throw InputError(fmt::format("far slice scale {} with casters receiver-mask-gpu: the GPU's caster filter needs layers of one "
                                 "size (choose receiver-pixels or receivers, or a scale of 1)", settings.farSliceScale));
}

}  // namespace

int sliceMapSize(const FrameSettings& settings, int slice, int cascades) {
  if (cascades < 2 || slice < cascades - 1) return settings.shadowMapSize;
  return static_cast<int>(std::lround(settings.farSliceScale * settings.shadowMapSize));
}

long long shadowTexels(const FrameSettings& settings, int cascades) {
  long long texels = 0;
  for (int i = 0; i < cascades; ++i) texels += static_cast<long long>(sliceMapSize(settings, i, cascades)) * sliceMapSize(settings, i, cascades);
  return texels;
}

std::string shadowLayoutLabel(const FrameSettings& settings, int cascades) {
  const int near = sliceMapSize(settings, 0, cascades), far = sliceMapSize(settings, cascades - 1, cascades);
  if (cascades == 1) return fmt::format("{}²", near);
  if (far == near) return fmt::format("{}×{}²", cascades, near);
  return fmt::format("{}{}²+{}²", cascades > 2 ? fmt::format("{}×", cascades - 1) : "", near, far);
}

ShadowSettings resolveCascades(const FrameSettings& settings, const Scene& scene) {
  ShadowSettings s = scene.shadows;
  s.cascades = settings.cascades.value_or(s.cascades);
  s.split_lambda = settings.splitLambda.value_or(s.split_lambda);
  s.cascade_blend = settings.cascadeBlend.value_or(s.cascade_blend);
  return s;
}

gl::TimingMode defaultTimingMode(const gl::ContextInfo& info) {
  return info.softwareRenderer ? gl::TimingMode::Profiling : gl::TimingMode::GpuQueries;
}

CasterSelection defaultCasterSelection(const gl::ContextInfo& info) {
  return info.softwareRenderer ? CasterSelection::ReceiverPixels : CasterSelection::Receivers;
}

culling::QueryMode defaultQueryMode(const gl::ContextInfo& info) {
  return info.softwareRenderer ? culling::QueryMode::Deterministic : culling::QueryMode::Async;
}

void FrameStats::setPassTimes(const gl::FrameTiming& timing) {
  for (const gl::PassTime& pass : timing.passes)
    if (const std::optional<FramePass> p = kFramePassNames.find(pass.pass)) passMs[*p] = pass.ms;
}

// The passes in the order they run (DESIGN §1), with their GPU resources, and what a frame tells
// the next (FrameHistory).
struct Frame::Passes {
  WorkerThreads cpuWorkers{hardwareParts()};  // the CPU's parallel work: the receiver mask, the record from pixels, hidden casters
  GeometryPass geometry;
  NearestDepthPass nearestDepth;  // for the cascades' splits
  ReceiverPixels receiverPixels;  // for CasterSelection::ReceiverPixels
  ShadowSetupPass shadowSetup;
  ShadowPlan plan;  // the shadow setup pass's output, kept from the last frame with sun and receivers
  ShadowPass shadow;
  FrameBlockBuffer frameBlock;  // what the full-screen passes read, once per frame
  ShadowTermPass shadowTerm;
  BlurPass blur;
  LightingPass lighting;
  std::unique_ptr<ImpostorAtlas> impostors;  // baked by the first frame with impostors
  FrameHistory history;
  FrameHistory::CullPlan cullPlan;  // this frame's

  Passes(const SceneObjects& objects, const terrain::Terrain* terrain, const vegetation::Forest* forest,
         const std::vector<PropBox>& props, int width, int height, const CullingSettings& culling)
      : geometry(objects, terrain, forest, props, width, height, culling),
        shadowSetup(cpuWorkers),
        shadow(objects, terrain, forest, props, cpuWorkers),
        shadowTerm(width, height),
        lighting(width, height, geometry.gbuffer()),
        history(objects, culling) {}
};

// What a frame is drawn with, resolved once at its start.
struct Frame::Inputs {
  const Camera& camera;
  double time;
  const FrameSettings& settings;
  glm::dvec3 l;            // the unit light direction
  bool sunBelowHorizon;
  DrawView eye;
  std::optional<terrain::TerrainLod> lod;  // the eye's terrain LOD (none without terrain)
  ShadowSettings cascades;                 // the settings' or the scene's
  ShadowLookupShape lookupShape;
  bool blurred, haze;
  int termScale;           // pixels per term texel side (1 with the blur off)
  TermSource termSource;   // where lighting takes the term from
  int blurTaps;            // the blur's tap bound (blurTapsBound; 0 with the blur off)
  bool readsPixels;  // the G-buffer is read back for the receiver mask (and the record of what showed)
  bool recordsInLighting;  // else the lighting pass records what shows (FrameHistory::recordsInLighting)
  const terrain::TerrainLod* eyeLod() const { return lod ? &*lod : nullptr; }
  LightingPass::ProgramKey lightingProgram() const { return {termSource, lookupShape, blurTaps, haze, recordsInLighting}; }
};

Frame::Frame(const Scene& scene, int width, int height) : scene_(scene), width_(width), height_(height) {
  if (width < 1 || height < 1) throw InputError("frame: width and height must be at least 1");
  auto start = std::chrono::steady_clock::now();
  const auto stepDone = [&](const char* name) {
    const auto now = std::chrono::steady_clock::now();
    startup_.push_back({name, std::chrono::duration<double, std::milli>(now - start).count(), residentMegabytes(), heapInUseMegabytes()});
    start = now;
  };
  if (scene.terrain) {
    terrain_ = std::make_unique<terrain::Terrain>(*scene.terrain);
    stepDone("terrain");
    if (scene.vegetation) forest_ = std::make_unique<vegetation::Forest>(*scene.vegetation, *terrain_);
    stepDone("trees");
  }
  objects_ = std::make_unique<SceneObjects>(terrain_.get(), forest_.get(), scene.props);
  stepDone("objects");
  passes_ = std::make_unique<Passes>(*objects_, terrain_.get(), forest_.get(), scene.props, width, height, scene.culling);
  glFinish();  // the upload's copies done, not only queued
  stepDone("gpu_upload");
  bvh_ = culling::Bvh(objects_->boxes(), scene.culling.leaf_size);
  culler_.setParameters(scene_.culling);
  for (const Aabb& b : objects_->boxes()) sceneBounds_.extend(b);
  stepDone("bvh");
}

Frame::~Frame() = default;

void Frame::moveTrees(std::span<const vegetation::Forest::Move> moves) {
  if (!forest_) throw InputError("moveTrees: the scene has no trees");
  forest_->moveTrees(moves);  // the tree renderers read the forest at every draw
  objects_->updateTrees(*forest_, moves);
  passes_->shadow.treesMoved();
  objectsMoved();
}

void Frame::propsMoved() {
  passes_->geometry.propsMoved(scene_.props);
  passes_->shadow.propsMoved(scene_.props);
  objects_->updateBoxes(forest_.get(), scene_.props);
  objectsMoved();
}

void Frame::objectsMoved() {
  // A rebuild renumbers the BVH's nodes: the culler's per-node history would belong to other
  // nodes, so it starts afresh (a refit keeps the nodes and their history).
  if (bvh_.refit(objects_->boxes())) culler_.reset();
  sceneBounds_ = Aabb();
  for (const Aabb& b : objects_->boxes()) sceneBounds_.extend(b);
}

void Frame::resetHistory() {
  culler_.reset();
  passes_->geometry.resetHistory();
  passes_->shadowSetup.reset();
  passes_->nearestDepth.reset();
  passes_->history.forget();
}

void Frame::renderReferenceGeometry(const Camera& camera, double time) {
  if (!referenceCuller_) referenceCuller_ = std::make_unique<culling::OcclusionCuller>();
  const std::optional<terrain::TerrainLod> lod = terrainLodFor(camera);
  passes_->geometry.run(camera, DrawView::fromCamera(camera, time, scene_.sun), lod ? &*lod : nullptr,
                        culling::CullingStrategy::Frustum, *referenceCuller_, bvh_, nullptr);
}

std::optional<terrain::TerrainLod> Frame::terrainLodFor(const Camera& camera) const {
  if (!terrain_) return std::nullopt;
  return terrain_->lodFor(camera, height_);
}

Camera Frame::startCamera() const {
  Camera c = scene_.startCamera();
  c.aspect = static_cast<double>(width_) / height_;
  if (scene_.camera.above_ground && terrain_)
    c.position.y = terrain_->heightAt(c.position.x, c.position.z) + *scene_.camera.above_ground;
  return c;
}

Camera Frame::cameraAt(const CameraPose& pose, bool aboveGround) const {
  Camera camera = startCamera();
  camera.position = pose.position;
  if (aboveGround && terrain_) camera.position.y += terrain_->heightAt(pose.position.x, pose.position.z);
  camera.yaw = glm::radians(pose.yaw_deg);
  camera.pitch = glm::radians(pose.pitch_deg);
  return camera;
}

int Frame::cascadeCount() const { return passes_->plan.cascades; }
int Frame::cascadeOf(double eyeDepth) const { return passes_->plan.sliceOf(eyeDepth); }

const std::vector<std::uint32_t>& Frame::visibleObjects() const { return passes_->history.visibleObjects(); }

const ShadowSlice& Frame::slice(int index) const {
  if (index < 0 || index >= passes_->plan.cascades)
    throw InputError(fmt::format("shadow slice {}: the last frame had {}", index, passes_->plan.cascades));
  return passes_->plan.slices[static_cast<size_t>(index)];
}
const shadows::ShadowSetup& Frame::shadowSetup(int index) const { return slice(index).setup; }
std::vector<std::uint32_t> Frame::casters(int index) const {
  const std::vector<std::uint32_t>& candidates = slice(index).casters;
  const std::optional<std::vector<std::uint32_t>> trees = passes_->shadow.treesTested(index);
  if (!trees) return candidates;
  std::vector<std::uint32_t> drawn = *trees;  // and the casters the GPU did not test: tiles, props
  for (std::uint32_t o : candidates)
    if (objects_->objects()[o].kind != SceneObjects::Kind::Tree) drawn.push_back(o);
  std::sort(drawn.begin(), drawn.end());
  return drawn;
}
const Camera& Frame::shadowCamera(int index) const { return slice(index).camera; }

// The frame as the design's stages (DESIGN §1), each a call on a named unit with its inputs and
// outputs as arguments.
FrameStats Frame::render(const Camera& camera, double time, const FrameSettings& settings) {
  validate(settings);
  const Inputs in = resolveInputs(camera, time, settings);
  FrameStats stats = beginFrame(in);
  Passes& p = *passes_;
  // 1. Geometry pass: the culler draws the G-buffer; the visible set and its z_f.
  const culling::CullingResult& culled = drawGeometry(in, stats);
  // 2. Shadow setup from the visible set: per slice B, the method's matrices and the casters.
  const culling::CullingResult& visible = setUpShadows(in, culled, stats);
  // 3. Shadow pass: the casters into a layer per slice, front faces culled.
  {
    auto timed = timer_->scope(passName(FramePass::Shadow));
    const bool gpuMask = settings.casters == CasterSelection::ReceiverMaskGpu && !in.sunBelowHorizon;
    stats.shadowTriangles = p.shadow.run(p.plan, in.eye, in.eyeLod(), settings, in.l, gpuMask ? &p.geometry.gbuffer().surface : nullptr, stats);
  }
  // 4. The frame block the full-screen passes read; the shadow term and the blur.
  const gl::Texture* blurredTerm = shadowTerm(in);
  // 5. Lighting: the term upsampled, blurred vertically or looked up (TermSource); the sky.
  {
    auto timed = timer_->scope(passName(FramePass::Lighting));
    p.lighting.run(p.geometry.gbuffer(), blurredTerm, in.lightingProgram(), p.shadow.map(), p.frameBlock, settings.keepShadowTerm);
    if (in.recordsInLighting) p.history.afterLighting();
  }
  endFrame(in, visible, stats);
  return stats;
}

std::string Frame::passName(FramePass pass) { return std::string(kFramePassNames.name(pass)); }

Frame::Inputs Frame::resolveInputs(const Camera& camera, double time, const FrameSettings& settings) const {
  const glm::dvec3 l = glm::normalize(scene_.sun.direction);
  const bool sunBelowHorizon = !(l.y < 0.0);  // light travelling upward comes from below the horizon
  const ShadowSettings cascades = resolveCascades(settings, scene_);
  const bool readsPixels = settings.casters == CasterSelection::ReceiverPixels && !sunBelowHorizon;
  const bool blurred = settings.blurRadius > 0.0;
  return Inputs{camera,
                time,
                settings,
                l,
                sunBelowHorizon,
                DrawView::fromCamera(camera, time, scene_.sun),
                terrainLodFor(camera),
                cascades,
                ShadowLookupShape{settings.pcfRadius, cascades.cascades},
                blurred,
                hazeDensityOf(settings, scene_) > 0.0,
                blurred ? settings.shadowTermScale : 1,
                !blurred ? TermSource::Lookup : settings.shadowTermScale > 1 ? TermSource::Upsample : TermSource::VerticalBlur,
                blurred ? blurTapsBound(settings.blurRadius, settings.shadowTermScale) : 0,
                readsPixels,
                passes_->history.recordsInLighting(readsPixels)};
}

// The programs this frame's passes use, compiled before any pass is timed; the timer's frame.
double Frame::useImpostors(const FrameSettings& settings, const Camera& camera) {
  Passes& p = *passes_;
  const bool on = settings.impostorDistance != 0.0 && forest_;
  if (on && !p.impostors) {
    p.impostors = std::make_unique<ImpostorAtlas>(*forest_);
    startup_.push_back({"impostor_bake", 1e3 * p.impostors->bakeSeconds(), residentMegabytes(), heapInUseMegabytes()});
  }
  ImpostorSwitch impostors{on ? settings.impostorDistance : 0.0, settings.impostorBand};
  if (impostors.distance == kImpostorDistanceAuto) impostors.distance = p.impostors->switchDistance(camera.fovy, height_);
  p.geometry.setImpostors(on ? p.impostors.get() : nullptr, impostors);
  p.shadow.setImpostors(on ? p.impostors.get() : nullptr, impostors);
  return impostors.distance;
}

FrameStats Frame::beginFrame(const Inputs& in) {
  Passes& p = *passes_;
  const double impostorDistance = useImpostors(in.settings, in.camera);
  if (in.blurred) {
    p.shadowTerm.prepare(in.lookupShape, in.termScale);
    p.blur.prepare(in.termScale, in.blurTaps);
  }
  p.lighting.prepare(in.lightingProgram());
  if (!timer_ || timer_->mode() != in.settings.timing) timer_ = std::make_unique<gl::PassTimer>(in.settings.timing, 3, framesRendered_);
  FrameStats stats;
  stats.sunBelowHorizon = in.sunBelowHorizon;
  stats.impostorDistance = impostorDistance;
  stats.frameNumber = framesRendered_++;
  timer_->beginFrame();
  return stats;
}

const culling::CullingResult& Frame::drawGeometry(const Inputs& in, FrameStats& stats) {
  auto timed = timer_->scope(passName(FramePass::Geometry));
  Passes& p = *passes_;
  culler_.setQueryMode(in.settings.queries);
  p.cullPlan = p.history.beforeCull(stats.frameNumber, in.camera, in.settings, in.readsPixels, culler_, p.geometry);
  stats.culledByFrustum = p.cullPlan.culledByFrustum;
  stats.hiddenByReprojection = p.cullPlan.hiddenByReprojection;
  const culling::CullingResult& culled = p.geometry.run(in.camera, in.eye, in.eyeLod(), p.cullPlan.strategy, culler_, bvh_, p.cullPlan.frozenSet);
  stats.culling = culled.stats;
  stats.geometryTriangles = culled.stats.trianglesDrawn;
  return culled;
}

// With cascades, the splits start from the nearest visible depth (NearestDepthPass); with the
// receiver pixels, the G-buffer is read back first (the receiver mask, the record of what showed).
const culling::CullingResult& Frame::setUpShadows(const Inputs& in, const culling::CullingResult& culled, FrameStats& stats) {
  auto timed = timer_->scope(passName(FramePass::ShadowSetup));
  Passes& p = *passes_;
  std::optional<double> nearest;
  if (in.cascades.cascades > 1) nearest = p.nearestDepth.run(p.geometry.gbuffer().depth, in.camera);
  const culling::CullingResult* visible = &culled;
  std::span<const std::uint8_t> shown;  // the objects with pixels: the casters' receivers
  if (in.readsPixels) {
    p.receiverPixels.read(p.geometry.gbuffer(), width_, height_, in.camera);
    visible = &p.history.afterReadback(p.receiverPixels, p.cpuWorkers, p.cullPlan, culled, in.camera);
    shown = p.history.shownInReadback();
  }
  p.shadowSetup.run(in.camera, *visible, in.settings, in.cascades, nearest, in.l, in.sunBelowHorizon, *objects_, bvh_, in.eyeLod(),
                    sceneBounds_, in.readsPixels ? &p.receiverPixels : nullptr, shown, p.plan, stats);
  stats.casterObjects = 0;
  for (int i = 0; i < p.plan.cascades; ++i) stats.casterObjects += static_cast<int>(p.plan.slices[static_cast<size_t>(i)].casters.size());
  stats.visibleObjects = static_cast<int>(visible->visibleObjects.size());
  stats.farDepth = visible->farDepth;
  return *visible;
}

// The frame block (with the record's stamp where the lighting pass records what shows); with the
// blur on, the shadow term into a texture and the blur (both halves at half resolution, the
// horizontal one at full), which lighting reads; with it off, lighting looks the term up itself (no
// full-screen pass writes it).
const gl::Texture* Frame::shadowTerm(const Inputs& in) {
  Passes& p = *passes_;
  {
    auto timed = timer_->scope(passName(FramePass::ShadowTerm));
    FrameBlock block = frameBlock(in.camera, p.plan, in.settings, in.termScale, scene_, in.l, !in.sunBelowHorizon);
    if (in.recordsInLighting) p.history.beforeLighting(block, in.camera);
    p.frameBlock.write(block);
    if (in.blurred) p.shadowTerm.run(p.geometry.gbuffer(), p.shadow.map(), in.lookupShape, in.termScale, p.frameBlock);
  }
  auto timed = timer_->scope(passName(FramePass::Blur));
  return in.blurred ? &p.blur.run(p.shadowTerm.term(), in.termScale, in.blurTaps, p.shadowTerm.blockDepth(), p.frameBlock) : nullptr;
}

// What the frame leaves for readers and for the next frame; the pass times where known.
void Frame::endFrame(const Inputs& in, const culling::CullingResult& visible, FrameStats& stats) {
  passes_->history.afterFrame(visible);
  wholeShadowMap_ = in.settings.wholeShadowMap;
  termWritten_ = in.blurred;
  usedTermKept_ = in.settings.keepShadowTerm;
  timer_->endFrame();
  if (in.settings.timing != gl::TimingMode::Profiling) {
    stats.passTimesPending = true;
    return;
  }
  while (timer_->takeOldestCompleted(passTiming_)) {
    stats.setPassTimes(passTiming_);
    passes_->history.learn(passTiming_);
  }
}

std::vector<gl::FrameTiming> Frame::takePassTimes() {
  if (!timer_ || timer_->mode() == gl::TimingMode::Profiling) return {};
  std::vector<gl::FrameTiming> timings = timer_->takeCompleted();
  for (const gl::FrameTiming& t : timings) passes_->history.learn(t);
  return timings;
}

std::vector<gl::FrameTiming> Frame::drainPassTimes() {
  if (!timer_ || timer_->mode() == gl::TimingMode::Profiling) return {};
  return timer_->drain();
}

void Frame::presentTo(GLuint framebuffer, int width, int height) const {
  glBlitNamedFramebuffer(passes_->lighting.framebuffer().id(), framebuffer, 0, 0, width_, height_, 0, 0, width, height,
                         GL_COLOR_BUFFER_BIT, GL_LINEAR);
}

PassFloorTimes Frame::timePassFloors(int repeats) {
  if (!floors_) floors_ = std::make_unique<PassFloors>(width_, height_);
  return floors_->time(passes_->geometry.gbuffer(), passes_->shadow.map(), std::max(1, repeats));
}

Image8 Frame::readColor() const {
  Image8 image(width_, height_, 4);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glGetTextureImage(passes_->lighting.color().id(), 0, GL_RGBA, GL_UNSIGNED_BYTE, static_cast<GLsizei>(image.pixels.size()),
                    image.pixels.data());
  flipRows(image);
  return image;
}

void Frame::requireUsedTerm(const char* reader) const {
  if (!usedTermKept_)
    throw Error(fmt::format("Frame::{}: the last frame did not keep the shadow term it lit with (FrameSettings::keepShadowTerm "
                            "was false, or no frame was rendered)", reader));
}

std::vector<float> Frame::readShadowTerm() const {
  // The blur off, the lighting pass looked the term up and wrote it as the term it used.
  if (!termWritten_) requireUsedTerm("readShadowTerm");
  const gl::Texture& term = termWritten_ ? passes_->shadowTerm.term() : passes_->lighting.usedTerm();
  std::vector<float> texels(static_cast<size_t>(term.width()) * term.height());
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glGetTextureImage(term.id(), 0, GL_RED, GL_FLOAT, static_cast<GLsizei>(texels.size() * 4), texels.data());
  if (term.width() == width_) return texels;
  // At half resolution: each pixel the texel of its block.
  std::vector<float> v(static_cast<size_t>(width_) * height_);
  const int scale = passes_->shadowTerm.scale();
  for (int y = 0; y < height_; ++y)
    for (int x = 0; x < width_; ++x)
      v[static_cast<size_t>(y) * width_ + x] = texels[static_cast<size_t>(y / scale) * term.width() + x / scale];
  return v;
}

std::vector<float> Frame::readBlurredShadowTerm() const {
  requireUsedTerm("readBlurredShadowTerm");
  std::vector<float> v(static_cast<size_t>(width_) * height_);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glGetTextureImage(passes_->lighting.usedTerm().id(), 0, GL_RED, GL_FLOAT, static_cast<GLsizei>(v.size() * 4), v.data());
  return v;
}

std::vector<std::uint32_t> Frame::readObjectIds() const {
  std::vector<glm::uvec4> surface(static_cast<size_t>(width_) * height_);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glGetTextureImage(passes_->geometry.gbuffer().surface.id(), 0, GL_RGBA_INTEGER, GL_UNSIGNED_INT,
                    static_cast<GLsizei>(surface.size() * sizeof(glm::uvec4)), surface.data());
  std::vector<std::uint32_t> v(surface.size());
  for (size_t i = 0; i < surface.size(); ++i) v[i] = surface[i].w;  // the object ID (shaders/gbuffer.frag)
  return v;
}

Frame::ShownInImage Frame::readShownInImage() {
  if (!passes_->history.collectRecord()) throw Error("Frame::readShownInImage: no frame recorded what showed ([culling] image_visibility)");
  const ImageVisibility& record = passes_->history.record();
  return {{record.shownObjects().begin(), record.shownObjects().end()}, {record.shownBlocks().begin(), record.shownBlocks().end()}};
}

int Frame::shadowMapSize(int slice) const { return passes_->shadow.size() == 0 ? 0 : this->slice(slice).mapSize; }

std::vector<float> Frame::readShadowMap(int layer) const {
  if (!wholeShadowMap_)
    throw Error("Frame::readShadowMap: the last frame drew only the texels its lookups read (FrameSettings::wholeShadowMap was false)");
  if (passes_->shadow.size() == 0) return {};
  if (layer < 0 || layer >= passes_->shadow.layers())
    throw InputError(fmt::format("shadow map layer {}: the map has {}", layer, passes_->shadow.layers()));
  const int size = shadowMapSize(layer);  // the square at the layer's origin (FrameSettings::farSliceScale)
  std::vector<float> v(static_cast<size_t>(size) * size);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glGetTextureSubImage(passes_->shadow.map().id(), 0, 0, 0, layer, size, size, 1, GL_DEPTH_COMPONENT, GL_FLOAT,
                       static_cast<GLsizei>(v.size() * 4), v.data());
  return v;
}

std::vector<float> Frame::readDepth() const {
  std::vector<float> v(static_cast<size_t>(width_) * height_);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glGetTextureImage(passes_->geometry.gbuffer().depth.id(), 0, GL_DEPTH_COMPONENT, GL_FLOAT, static_cast<GLsizei>(v.size() * 4), v.data());
  return v;
}

}  // namespace forest::render
