#include "geometry_pass.hpp"

namespace forest::render {

GBuffer::GBuffer(int width, int height)
    : surface(GL_RGBA32UI, width, height), depth(GL_DEPTH_COMPONENT32F, width, height) {
  framebuffer.attach(GL_COLOR_ATTACHMENT0, surface);
  framebuffer.attach(GL_DEPTH_ATTACHMENT, depth);
  framebuffer.checkComplete("G-buffer");
  for (const gl::Texture* t : {&surface, &depth}) {
    glTextureParameteri(t->id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(t->id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    // Gathers at the image's edge (the half-resolution term's blocks) read the edge again.
    glTextureParameteri(t->id(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(t->id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  }
}

namespace {
// Texels per side of the ground cover: 2.3 m each on the default 1.2 km terrain, finer than the
// stands' soft edges (tens of metres).
constexpr int kGroundCoverSide = 512;
}  // namespace

GeometryPass::GeometryPass(const SceneObjects& objects, const terrain::Terrain* terrain, const vegetation::Forest* forest,
                           const std::vector<PropBox>& props, int width, int height, const CullingSettings& culling)
    : objects_(objects), width_(width), height_(height), gbuffer_(width, height) {
  if (terrain && culling.terrain_blocks) blockVisibility_.emplace(*terrain, culling.visible_requery_frames);
  blockResult_.visibleObjects.reserve(objects.boxes().size());  // copied into every frame: never grown
  if (terrain) terrain_ = std::make_unique<TerrainRenderer>(*terrain, TerrainRenderer::Output::GBuffer, objects.terrainIdBase());
  if (terrain_ && forest && forest->stands()) {  // forest floor under the stands (terrain.frag)
    const terrain::Heightfield& h = terrain->heightfield();
    const glm::dvec2 lo = h.origin(), hi = lo + glm::dvec2(h.size());
    terrain_->setGroundCover(forest->stands()->densityGrid(kGroundCoverSide, lo, hi), kGroundCoverSide);
  }
  if (forest) trees_ = std::make_unique<TreeRenderer>(*forest, SurfaceOutput::GBuffer, objects.treeIdBase());
  props_ = std::make_unique<PropRenderer>(props, SurfaceOutput::GBuffer, objects.propIdBase());
  drawer_ = std::make_unique<SceneDrawer>(objects, terrain_.get(), trees_.get(), props_.get(), DrawView{}, nullptr);
}

const culling::CullingResult& GeometryPass::run(const Camera& camera, const DrawView& eye, const terrain::TerrainLod* lod,
                                         culling::CullingStrategy strategy, culling::OcclusionCuller& culler,
                                         const culling::Bvh& bvh, const std::vector<std::uint32_t>* frozen) {
  glBindFramebuffer(GL_FRAMEBUFFER, gbuffer_.framebuffer.id());
  glViewport(0, 0, width_, height_);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_GREATER);  // reversed-Z
  glDepthMask(GL_TRUE);
  glEnable(GL_CULL_FACE);
  glCullFace(GL_BACK);
  glDisable(GL_POLYGON_OFFSET_FILL);
  // Eye depth 0 marks the sky for the full-screen passes, ID 0 no object (shaders/gbuffer.frag).
  const GLuint nothingDrawn[4] = {0, 0, 0, 0};
  glClearBufferuiv(GL_COLOR, 0, nothingDrawn);
  const float farDepth = 0.0f;
  glClearBufferfv(GL_DEPTH, 0, &farDepth);
  SceneDrawer& drawer = *drawer_;
  drawer.setView(eye, lod);
  frustum_.emplace(camera);
  const bool byBlock = !frozen && blockVisibility_ && lod && strategy != culling::CullingStrategy::None &&
                       strategy != culling::CullingStrategy::Frustum;
  drawer.cullTerrainBlocks(&*frustum_, byBlock ? &*blockVisibility_ : nullptr);
  if (blockVisibility_ && !byBlock) blockVisibility_->skipFrame();
  if (!frozen) {
    const culling::QueryShapes shapes = objects_.queryShapes(lod);  // rewritten per call: once a frame
    if (!byBlock) return culler.cull(bvh, objects_.boxes(), camera, strategy, drawer, shapes);
    // After the traversal: at most every object and every block, and their boxes.
    const std::size_t blocks = objects_.tileCount() * terrain::Terrain::kMaxBlockBoxes;
    culler.reserveAfterCull(objects_.boxes().size() + blocks, objects_.queryBoxCount() + blocks);
    blockVisibility_->beginFrame(drawer);
    // The blocks' queries go out with the traversal's last batch (chc++: no wait of their own).
    const culling::CullingResult& culled = culler.cull(bvh, objects_.boxes(), camera, strategy, drawer, shapes, &*blockVisibility_);
    const long long late = blockVisibility_->drawLate(culler);  // its queries are counted in culled.stats
    // Objects found visible before the blocks held back were drawn may be hidden behind them.
    if (!culling::confirmsFoundLeaves(strategy)) (void)culler.refineVisibleSet(objects_.boxes(), shapes);
    blockResult_ = culled;
    blockResult_.stats.trianglesDrawn += late;
    return blockResult_;
  }
  culling::CullingResult& visible = frozenResult_;
  visible.stats = culling::CullingStats{};
  visible.visibleObjects = *frozen;
  visible.stats.trianglesDrawn = drawer.draw(visible.visibleObjects);
  visible.stats.objectsDrawn = static_cast<int>(visible.visibleObjects.size());
  visible.farDepth = culling::farDepthOf(visible.visibleObjects, objects_.boxes(), camera);
  return visible;
}

}  // namespace forest::render
