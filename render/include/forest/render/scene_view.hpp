#pragma once
// What `forest render` draws of a scene today: the terrain (if the scene has one) and the props,
// lit by the sun without shadows. The full frame (culling, shadows) replaces it in "The frame I".
#include <memory>
#include <optional>

#include "forest/core/scene.hpp"
#include "forest/render/prop_renderer.hpp"
#include "forest/render/terrain_renderer.hpp"
#include "forest/terrain/terrain.hpp"

namespace forest::render {

class SceneView {
 public:
  // Generates the terrain and uploads everything (needs a current GL context).
  explicit SceneView(const Scene& scene);

  struct Stats {
    TerrainRenderer::Stats terrain;
    int propTriangles = 0;
  };
  // Clears the bound framebuffer to the sky (reversed-Z depth 0) and draws.
  Stats draw(const Camera& camera, int viewportHeight) const;

  const terrain::Terrain* terrain() const { return terrain_.get(); }

 private:
  const Scene& scene_;
  std::unique_ptr<terrain::Terrain> terrain_;
  std::unique_ptr<TerrainRenderer> terrainRenderer_;
  PropRenderer props_;
};

}  // namespace forest::render
