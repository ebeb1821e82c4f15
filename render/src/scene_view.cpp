#include "forest/render/scene_view.hpp"

namespace forest::render {

SceneView::SceneView(const Scene& scene) : scene_(scene), props_(scene.props) {
  if (scene.terrain) {
    terrain_ = std::make_unique<terrain::Terrain>(*scene.terrain);
    terrainRenderer_ = std::make_unique<TerrainRenderer>(*terrain_);
    if (scene.vegetation) {
      forest_ = std::make_unique<vegetation::Forest>(*scene.vegetation, *terrain_);
      treeRenderer_ = std::make_unique<TreeRenderer>(*forest_);
    }
  }
}

Camera SceneView::startCamera() const {
  Camera camera = scene_.startCamera();
  if (scene_.camera.above_ground && terrain_)
    camera.position.y = terrain_->heightAt(camera.position.x, camera.position.z) + *scene_.camera.above_ground;
  return camera;
}

SceneView::Stats SceneView::draw(const Camera& camera, int viewportHeight, double time) const {
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
  if (treeRenderer_) stats.trees = treeRenderer_->draw(camera, treeRenderer_->clustersInFrustum(camera), time, scene_.sun);
  props_.draw(camera, scene_.sun);
  stats.propTriangles = props_.triangleCount();
  return stats;
}

}  // namespace forest::render
