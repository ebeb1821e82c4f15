#pragma once
// The Embree mirror of what the renderer draws for one camera and time: the terrain tiles as the
// LOD morphs them (Terrain::drawnTriangles, the CPU twin of terrain.vert) and every tree at the
// LOD and sway the GPU gives it. Object IDs follow the renderer's: tiles from `terrainIdBase`,
// trees from `treeIdBase`.
#include <cstdint>
#include <vector>

#include "forest/core/camera.hpp"
#include "forest/raytrace/ray_scene.hpp"
#include "forest/terrain/terrain.hpp"
#include "forest/vegetation/forest.hpp"

namespace forest::raytrace {

struct MirrorOptions {
  std::uint32_t terrainIdBase = 1;
  std::uint32_t treeIdBase = 1;
  double time = 0.0;
};

// Adds the terrain (may be null) and the forest (may be null) to `scene` and commits it.
void mirrorScene(RayScene& scene, const terrain::Terrain* terrain, const terrain::TerrainLod* lod,
                 const vegetation::Forest* forest, const Camera& camera, const MirrorOptions& options);

// Object ID at every pixel centre (kNoObject for sky), rows bottom-up as OpenGL stores them,
// `width` × `height`. Rays run from the eye; hits nearer than the near plane or beyond the far
// plane count as sky, as the rasteriser clips them.
std::vector<std::uint32_t> traceObjectIds(const RayScene& scene, const Camera& camera, int width, int height);

}  // namespace forest::raytrace
