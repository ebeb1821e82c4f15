#pragma once
// What `forest render` draws of a scene today: the terrain and trees (if the scene has them) and
// the props, lit by the sun without shadows. The full frame (culling, shadows) replaces it in
// "The frame I".
#include <memory>

#include "forest/core/scene.hpp"
#include "forest/render/prop_renderer.hpp"
#include "forest/render/terrain_renderer.hpp"
#include "forest/render/tree_renderer.hpp"
#include "forest/terrain/terrain.hpp"
#include "forest/vegetation/forest.hpp"

namespace forest::render {

class SceneView {
 public:
  // Generates the terrain and the forest and uploads everything (needs a current GL context).
  explicit SceneView(const Scene& scene);

  struct Stats {
    TerrainRenderer::Stats terrain;
    TreeRenderer::Stats trees;
    int propTriangles = 0;
  };
  // Clears the bound framebuffer to the sky (reversed-Z depth 0) and draws at `time` (wind).
  Stats draw(const Camera& camera, int viewportHeight, double time = 0.0) const;

  // The scene's start camera, standing camera.above_ground over the terrain when that is set.
  Camera startCamera() const;

  const terrain::Terrain* terrain() const { return terrain_.get(); }
  const vegetation::Forest* forest() const { return forest_.get(); }

 private:
  const Scene& scene_;
  std::unique_ptr<terrain::Terrain> terrain_;
  std::unique_ptr<TerrainRenderer> terrainRenderer_;
  std::unique_ptr<vegetation::Forest> forest_;
  std::unique_ptr<TreeRenderer> treeRenderer_;
  PropRenderer props_;
};

}  // namespace forest::render
