#include "shadow_pass.hpp"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <chrono>

#include "forest/shadows/casters.hpp"
#include "forest/shadows/focus_body.hpp"

namespace forest::render {
namespace {

using glm::dvec3;

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

}  // namespace

int ShadowPass::countOtherThanTrees(std::span<const std::uint32_t> casters) const {
  return static_cast<int>(std::count_if(casters.begin(), casters.end(), [&](std::uint32_t o) {
    return objects_.objects()[o].kind != SceneObjects::Kind::Tree;
  }));
}

glm::dmat4 eyeRelativeToShadowClip(const shadows::ShadowSetup& setup, const dvec3& eye) {
  return zeroToOneDepth() * setup.worldToShadowClip * glm::translate(glm::dmat4(1.0), eye);
}

ShadowPass::ShadowPass(const SceneObjects& objects, const terrain::Terrain* terrain, const vegetation::Forest* forest,
                       const std::vector<PropBox>& props, WorkerThreads& workers)
    : objects_(objects),
      workers_(workers), terrainSource_(terrain), forestSource_(forest), propsSource_(props), cache_(objects, terrain, forest) {
  if (terrain) terrain_ = std::make_unique<TerrainRenderer>(*terrain, TerrainRenderer::Output::ObjectId, objects.terrainIdBase());
  if (forest) trees_ = std::make_unique<TreeRenderer>(*forest, SurfaceOutput::ObjectId, objects.treeIdBase());
  props_ = std::make_unique<PropRenderer>(props, SurfaceOutput::ObjectId, objects.propIdBase());
  drawer_ = std::make_unique<SceneDrawer>(objects, nullptr, trees_.get(), props_.get(), DrawView{}, nullptr);
  tiles_.reserve(objects.tileCount());
}

void ShadowPass::propsMoved(const std::vector<PropBox>& props) {
  cache_.forget();
  for (PropRenderer* r : {props_.get(), propsLightDepth_.get()})
    if (r) r->update(props);
}

void ShadowPass::setImpostors(const ImpostorAtlas* atlas, const ImpostorSwitch& impostors) {
  impostorAtlas_ = atlas;
  impostors_ = impostors;
  for (TreeRenderer* r : {trees_.get(), treesLightDepth_.get()})
    if (r) r->setImpostors(atlas, impostors);
}

void ShadowPass::ensureLightDepthRenderers() {
  if (propsLightDepth_) return;
  if (terrainSource_)
    terrainLightDepth_ = std::make_unique<TerrainRenderer>(*terrainSource_, TerrainRenderer::Output::LightDepth, objects_.terrainIdBase());
  if (forestSource_) {
    treesLightDepth_ = std::make_unique<TreeRenderer>(*forestSource_, SurfaceOutput::LightDepth, objects_.treeIdBase());
    treesLightDepth_->setImpostors(impostorAtlas_, impostors_);
  }
  propsLightDepth_ = std::make_unique<PropRenderer>(propsSource_, SurfaceOutput::LightDepth, objects_.propIdBase());
  lightDepthDrawer_ = std::make_unique<SceneDrawer>(objects_, nullptr, treesLightDepth_.get(), propsLightDepth_.get(),
                                                    DrawView{}, nullptr);
}

void ShadowPass::ensureMap(int size, int layers) {
  if (size == size_ && layers == layers_) return;
  map_ = gl::Texture(GL_DEPTH_COMPONENT32F, size, size, 1, layers);
  // Hardware 2×2 PCF: linear filtering of depth comparisons.
  glTextureParameteri(map_.id(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTextureParameteri(map_.id(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTextureParameteri(map_.id(), GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
  glTextureParameteri(map_.id(), GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
  glTextureParameteri(map_.id(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(map_.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  framebuffers_.clear();
  idsBesideMap_ = 0;  // the ID layers' framebuffers held the old map (its name may come back)
  for (int layer = 0; layer < layers; ++layer) {
    gl::Framebuffer& framebuffer = framebuffers_.emplace_back();
    framebuffer.attachLayer(GL_DEPTH_ATTACHMENT, map_, layer);
    glNamedFramebufferDrawBuffer(framebuffer.id(), GL_NONE);
    framebuffer.checkComplete("shadow map layer");
  }
  size_ = size;
  layers_ = layers;
}

void ShadowPass::useGpuFilter(bool use) {
  if (use && !gpuFilter_) gpuFilter_ = std::make_unique<GpuCasterFilter>(*forestSource_, objects_.treeIdBase());
  if (use) {
    ensureLightDepthRenderers();
    ensureIdLayers();
  }
  for (TreeRenderer* r : {trees_.get(), treesLightDepth_.get()})
    if (r) r->setCasterFilter(use ? gpuFilter_.get() : nullptr);
  if (use) gpuFilter_->beginFrame(true);
  filteredOnGpu_ = use;
}

// The object-ID layers beside the map's for the GPU's caster filter (which trees counted), and a
// framebuffer per layer with both; the map's own framebuffers keep depth alone.
void ShadowPass::ensureIdLayers() {
  if (idsBesideMap_ == map_.id()) return;  // made for this map (ensureMap resets it)
  idsBesideMap_ = map_.id();
  ids_ = gl::Texture(GL_R32UI, size_, size_, 1, layers_);
  glTextureParameteri(ids_.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(ids_.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  idFramebuffers_.clear();
  for (int layer = 0; layer < layers_; ++layer) {
    gl::Framebuffer& framebuffer = idFramebuffers_.emplace_back();
    framebuffer.attachLayer(GL_DEPTH_ATTACHMENT, map_, layer);
    framebuffer.attachLayer(GL_COLOR_ATTACHMENT0, ids_, layer);
    glNamedFramebufferDrawBuffer(framebuffer.id(), GL_COLOR_ATTACHMENT0);
    framebuffer.checkComplete("shadow map layer with object IDs");
  }
}

std::optional<std::vector<std::uint32_t>> ShadowPass::treesTested(int slice) const {
  if (!filteredOnGpu_) return slice >= 0 && slice < shadows::kMaxCascades ? treesOccluded_[static_cast<size_t>(slice)] : std::nullopt;
  std::vector<std::uint32_t> trees = gpuFilter_->selectedIds(slice);
  for (std::uint32_t& id : trees) id = static_cast<std::uint32_t>(objects_.objectOfId(id));
  std::sort(trees.begin(), trees.end());
  return trees;
}

long long ShadowPass::run(const ShadowPlan& plan, const DrawView& eye, const terrain::TerrainLod* lod,
                          const FrameSettings& settings, const dvec3& l, const gl::Texture* receiverSurface, FrameStats& stats) {
  ensureMap(plan.layerSide(), plan.cascades);
  useGpuFilter(receiverSurface != nullptr && forestSource_ != nullptr);
  // Cached slices need the casters known on the CPU (not the GPU's filter).
  const bool caching = settings.cacheSlices && !filteredOnGpu_;
  if (!caching) cache_.forget();
  long long triangles = 0;
  const bool profiling = settings.timing == gl::TimingMode::Profiling;
  // The read-back path culls the trees hidden from the sun (its layers drawn whole: not cached).
  const bool occluding = settings.hiddenCasters != HiddenCasters::Draw && !filteredOnGpu_ && !caching && forestSource_ != nullptr;
  if (occluding && !occlusion_) occlusion_ = std::make_unique<CasterOcclusion>(objects_, workers_);
  if (occluding) occlusion_->beginFrame();
  for (std::optional<std::vector<std::uint32_t>>& trees : treesOccluded_) trees.reset();
  for (int i = 0; i < plan.cascades; ++i) {
    const auto start = std::chrono::steady_clock::now();
    const ShadowSlice& slice = plan.slices[static_cast<size_t>(i)];
    CascadeStats& out = stats.cascade[static_cast<size_t>(i)];
    // The casters drawn only into the texels a lookup can read, when known and the whole map is
    // not asked for. A layer no lookup reads is left as it was.
    const bool scissored = !settings.wholeShadowMap && slice.texelsRead.has_value();
    const shadows::TexelRect read = scissored ? *slice.texelsRead : shadows::TexelRect{0, 0, slice.mapSize, slice.mapSize};
    const bool draws = plan.shadowed && !slice.setup.empty && !read.empty();
    const LayerTarget target{map_.id(), size_, slice.mapSize, layers_, settings.slopeScaleBias, settings.backside};
    LayerDraw layer{SliceUpdate::Redraw, caching ? "empty" : "off", "", slice.casters, slice.terrainBlocks, read};
    // Staggered: slice i redraws for its held casters' changes at most every 2^i frames.
    if (caching && draws) layer = cache_.plan(i, target, slice, read, eye, lod, l, settings.staggerSlices ? (1 << i) - 1 : 0);
    out.redraw = layer.why;
    out.deferred = layer.deferred;
    out.update = layer.update;
    long long drawn = 0;
    if (layer.update != SliceUpdate::Reuse) {
      drawn = drawLayer(i, plan, slice, layer, scissored, eye, lod, settings, l, receiverSurface, stats);
      if (caching && draws)
        cache_.drawn(i, target, layer, slice, eye, lod);
      else
        cache_.forget(i);
    }
    out.texelsDrawn = layer.update == SliceUpdate::Reuse ? 0 : layer.rect.texels();
    out.triangles = drawn;
    triangles += drawn;
    if (profiling) {  // serialised like the pass timer's own brackets (gl::TimingMode::Profiling)
      glFinish();
      out.shadowMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    }
  }
  return triangles;
}

long long ShadowPass::drawLayer(int i, const ShadowPlan& plan, const ShadowSlice& slice, const LayerDraw& layer, bool scissored,
                                const DrawView& eye, const terrain::TerrainLod* lod, const FrameSettings& settings, const dvec3& l,
                                const gl::Texture* receiverSurface, FrameStats& stats) {
  // With the GPU's filter or the read-back path's occlusion, the object-ID layer too (which trees
  // counted), unless the method writes the linear light depth (its programs write no ID).
  const bool occluded = occlusion_ && settings.hiddenCasters != HiddenCasters::Draw && !filteredOnGpu_ && slice.receiverMask &&
                        layer.update == SliceUpdate::Redraw && !settings.cacheSlices && !slice.setup.linearDepth &&
                        (settings.hiddenCasters == HiddenCasters::Cull || occlusion_->worthCulling(layer.casters, layer.rect.texels(), eye.lodEye, drawnImpostors()));
  const bool withIds = (filteredOnGpu_ || occluded) && !slice.setup.linearDepth;
  if (withIds) ensureIdLayers();
  glBindFramebuffer(GL_FRAMEBUFFER, (withIds ? idFramebuffers_ : framebuffers_)[static_cast<size_t>(i)].id());
  glViewport(0, 0, slice.mapSize, slice.mapSize);  // the square at the layer's origin (FrameSettings::farSliceScale)
  // The clear stays whole: under a scissor llvmpipe clears by drawing a quad, slower than its fast
  // clear of the whole layer.
  const shadows::TexelRect& read = layer.rect;
  const float nearLight = 1.0f;
  const bool clears = layer.update == SliceUpdate::Redraw;  // an addition draws into what the layer holds
  if (clears && !read.empty()) glClearBufferfv(GL_DEPTH, 0, &nearLight);
  const GLuint noObject[4] = {0, 0, 0, 0};
  if (clears && withIds) glClearBufferuiv(GL_COLOR, 0, noObject);
  if (scissored) {
    glEnable(GL_SCISSOR_TEST);
    glScissor(read.x0, read.y0, std::max(read.x1 - read.x0, 0), std::max(read.y1 - read.y0, 0));
  }
  const bool draws = plan.shadowed && !slice.setup.empty && !read.empty();
  if (draws && filteredOnGpu_)
    gpuFilter_->buildMask(i, *receiverSurface, slice.camera, slice.camera.near, slice.camera.far, slice.setup, eye.origin, map_,
                          withIds ? &ids_ : nullptr, plan.lookupReachTexels);
  long long drawn = 0;
  if (draws && occluded)
    drawn = drawWithOcclusion(i, slice, layer, plan.lookupReachTexels, eye, lod, settings, l, stats);
  else if (draws)
    drawn = drawSlice(slice, layer, eye, lod, settings, l, stats.shadowTerrainTriangles);
  if (draws && filteredOnGpu_) gpuFilter_->markCounted();
  if (scissored) glDisable(GL_SCISSOR_TEST);
  // The trees the GPU kept and drew (the draws count none): read back where the pipeline is
  // serialised anyway (Profiling timing); with timer queries the frame does not wait for them
  // and the slice's triangles leave them out.
  CascadeStats& out = stats.cascade[static_cast<size_t>(i)];
  if (draws && filteredOnGpu_ && settings.timing == gl::TimingMode::Profiling) {
    drawn += gpuFilter_->selectedTriangles(i);
    const int kept = static_cast<int>(gpuFilter_->selectedCount(i)) + countOtherThanTrees(slice.casters);
    stats.casterObjects += kept - out.casters;
    out.casters = kept;
  }
  return drawn;
}

long long ShadowPass::drawWithOcclusion(int i, const ShadowSlice& slice, const LayerDraw& layer, double reach, const DrawView& eye,
                                        const terrain::TerrainLod* lod, const FrameSettings& settings, const dvec3& l, FrameStats& stats) {
  const shadows::TexelRect& rect = layer.rect;
  const size_t texels = static_cast<size_t>(rect.texels());
  const GLsizei width = rect.x1 - rect.x0, height = rect.y1 - rect.y0;
  occlusion_->split(layer.casters, first_, others_);
  LayerDraw phase = layer;
  phase.casters = first_;
  long long drawn = drawSlice(slice, phase, eye, lod, settings, l, stats.shadowTerrainTriangles);
  depthsRead_.resize(texels);
  glGetTextureSubImage(map_.id(), 0, rect.x0, rect.y0, i, width, height, 1, GL_DEPTH_COMPONENT, GL_FLOAT,
                       static_cast<GLsizei>(texels * sizeof(float)), depthsRead_.data());
  occlusion_->keepUnhidden(slice.setup, slice.mapSize, *slice.receiverMask, reach, rect, depthsRead_, eye.lodEye, drawnImpostors(),
                           others_);
  phase.casters = others_;
  phase.blocks = {};  // the terrain went with the first draw
  const auto secondDraw = std::chrono::steady_clock::now();
  drawn += drawSlice(slice, phase, eye, lod, settings, l, stats.shadowTerrainTriangles);
  idsRead_.resize(texels);
  glGetTextureSubImage(ids_.id(), 0, rect.x0, rect.y0, i, width, height, 1, GL_RED_INTEGER, GL_UNSIGNED_INT,
                       static_cast<GLsizei>(texels * sizeof(std::uint32_t)), idsRead_.data());
  // The read waited for the draw: its wall time prices the trees worthCulling weighs.
  occlusion_->measuredCosts(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - secondDraw).count(), others_,
                            eye.lodEye, drawnImpostors());
  occlusion_->markCounted(*slice.receiverMask, reach, rect, idsRead_);
  // What the layer drew: the trees of both draws, for the statistics and the truth.
  std::vector<std::uint32_t>& trees = treesOccluded_[static_cast<size_t>(i)].emplace(others_);
  for (std::uint32_t o : first_)
    if (objects_.objects()[o].kind == SceneObjects::Kind::Tree) trees.push_back(o);
  std::sort(trees.begin(), trees.end());
  CascadeStats& out = stats.cascade[static_cast<size_t>(i)];
  const int kept = static_cast<int>(first_.size() + others_.size());
  stats.casterObjects += kept - out.casters;
  out.casters = kept;
  return drawn;
}

long long ShadowPass::drawSlice(const ShadowSlice& slice, const LayerDraw& layer, const DrawView& eye, const terrain::TerrainLod* lod,
                                const FrameSettings& settings, const dvec3& l, long long& terrainTriangles) {
  const shadows::ShadowSetup& setup = slice.setup;
  glDepthFunc(GL_LESS);
  // Which faces are "front" for the light: a face turned toward the sun must wind
  // counter-clockwise in the shadow map, unless the light matrix mirrors its image plane.
  glFrontFace(lightMirrorsWinding(setup, l) ? GL_CW : GL_CCW);
  glCullFace(settings.backside ? GL_FRONT : GL_BACK);
  if (settings.slopeScaleBias > 0.0) {
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(static_cast<float>(settings.slopeScaleBias), 0.0f);
  }
  DrawView light = eye;  // the eye's origin and LOD, seen from the light
  light.viewProjectionRelative = eyeRelativeToShadowClip(setup, eye.origin);
  light.fromSun = true;
  long long triangles = 0, terrain = 0;
  if (setup.linearDepth) {
    // TSM §4: the shaders write the linear light depth (and add the slope bias themselves).
    ensureLightDepthRenderers();
    const glm::dvec4& row = setup.worldToLightDepth;
    light.lightDepthRelative = glm::dvec4(dvec3(row), row.w + glm::dot(dvec3(row), eye.origin));
    light.depthSlopeBias = settings.slopeScaleBias;
    glDisable(GL_POLYGON_OFFSET_FILL);
    if (terrainLightDepth_ && lod) terrain = drawTerrain(*terrainLightDepth_, slice, layer, light, *lod);
    lightDepthDrawer_->setView(light, lod);
    triangles = lightDepthDrawer_->draw(layer.casters);
  } else {
    // The terrain first: with the GPU's caster filter it hides trees from the light (GpuCasterFilter).
    if (terrain_ && lod) terrain = drawTerrain(*terrain_, slice, layer, light, *lod);
    drawer_->setView(light, lod);
    triangles = drawer_->draw(layer.casters);
  }
  terrainTriangles += terrain;
  glDisable(GL_POLYGON_OFFSET_FILL);
  glFrontFace(GL_CCW);
  glCullFace(GL_BACK);
  glDepthFunc(GL_GREATER);
  return triangles + terrain;
}

long long ShadowPass::drawTerrain(const TerrainRenderer& renderer, const ShadowSlice& slice, const LayerDraw& layer,
                                  const DrawView& light, const terrain::TerrainLod& lod) {
  if (slice.terrainByBlock) return renderer.drawBlocks(light, lod, layer.blocks).triangles;
  tiles_.clear();
  for (std::uint32_t o : layer.casters) {
    const SceneObjects::Object& object = objects_.objects()[o];
    if (object.kind == SceneObjects::Kind::Tile) tiles_.push_back(static_cast<int>(object.index));
  }
  return renderer.draw(light, lod, tiles_).triangles;
}

}  // namespace forest::render
