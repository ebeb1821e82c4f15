#include "forest/render/scene_view.hpp"

namespace forest::render {

SceneView::SceneView(const Scene& scene) : scene_(scene), props_(scene.props) {
  if (scene.terrain) {
    terrain_ = std::make_unique<terrain::Terrain>(*scene.terrain);
    terrainRenderer_ = std::make_unique<TerrainRenderer>(*terrain_);
  }
}

SceneView::Stats SceneView::draw(const Camera& camera, int viewportHeight) const {
  const glm::vec3 sky(scene_.render.sky_color);
  glClearColor(sky.r, sky.g, sky.b, 1.0f);
  glClearDepth(0.0);  // reversed-Z: far = 0
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_GREATER);
  glEnable(GL_CULL_FACE);
  glCullFace(GL_BACK);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  Stats stats;
  if (terrainRenderer_) {
    const std::vector<int> tiles = terrainRenderer_->tilesInFrustum(camera);
    stats.terrain = terrainRenderer_->draw(camera, terrain_->lodFor(camera, viewportHeight), scene_.sun, tiles);
  }
  props_.draw(camera, scene_.sun);
  stats.propTriangles = props_.triangleCount();
  return stats;
}

}  // namespace forest::render
