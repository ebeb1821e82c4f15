#pragma once
// The Embree mirror of what the renderer draws for one camera and time: the terrain tiles as the
// LOD morphs them (Terrain::drawnTriangles, the CPU twin of terrain.vert), every tree at the
// LOD and sway the GPU gives it, and the props (closed boxes). Object IDs follow the renderer's: tiles from `terrainIdBase`,
// trees from `treeIdBase`, props from `propIdBase`.
#include <cstdint>
#include <vector>

#include "forest/core/camera.hpp"
#include "forest/core/scene.hpp"
#include "forest/raytrace/ray_scene.hpp"
#include "forest/terrain/terrain.hpp"
#include "forest/vegetation/forest.hpp"

namespace forest::raytrace {

struct MirrorOptions {
  std::uint32_t terrainIdBase = 1;
  std::uint32_t treeIdBase = 1;
  std::uint32_t propIdBase = 1;
  double time = 0.0;
  const std::vector<PropBox>* props = nullptr;  // boxes, as the renderer draws them
  const std::vector<std::uint32_t>* trees = nullptr;  // only these trees (indices); null: every tree
};

// Adds the terrain (may be null), the forest (may be null) and the props to `scene` and commits it.
void mirrorScene(RayScene& scene, const terrain::Terrain* terrain, const terrain::TerrainLod* lod,
                 const vegetation::Forest* forest, const Camera& camera, const MirrorOptions& options);

// Object ID at every pixel centre (kNoObject for sky), rows bottom-up as OpenGL stores them,
// `width` × `height`. Rays run from the eye; hits nearer than the near plane or beyond the far
// plane count as sky, as the rasteriser clips them.
std::vector<std::uint32_t> traceObjectIds(const RayScene& scene, const Camera& camera, int width, int height);

}  // namespace forest::raytrace
