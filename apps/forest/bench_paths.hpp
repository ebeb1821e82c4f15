#pragma once
// The camera paths of forest bench culling: four built-in paths through a scene (under the canopy
// of the densest stand, a ground-level walk, an open view above the canopy, a crossing of the
// highest hill) and a camera path file sampled as forest walkthrough samples it.
#include <string>
#include <vector>

#include "forest/core/camera.hpp"
#include "forest/core/camera_path.hpp"
#include "forest/core/scene.hpp"
#include "forest/terrain/terrain.hpp"
#include "forest/vegetation/forest.hpp"

namespace forest::app {

// A camera path file's first `frames` frames sampled at `fps` from its start, as forest walkthrough
// flies it (Frame::cameraAt).
std::vector<Camera> filePath(const CameraPath& path, const Scene& scene, const terrain::Terrain& terrain, int frames, double fps,
                             double aspect);
// The built-in path `kind` ("forest", "ground", "canopy", "hill").
std::vector<Camera> benchPath(const std::string& kind, const Scene& scene, const terrain::Terrain& terrain, const vegetation::Forest& forest,
                              int frames, double aspect);
// What the built-in path `kind` is and how far it moves and turns per frame (of `frames`), for the
// tables and the JSON.
std::string pathDescription(const std::string& kind, int frames);

// The scene with `trees` trees at the full scene's stand density: on a square of the terrain of
// trees / count of its area, centred on the path's keys (moved inside the terrain where it would
// reach past an edge). forest bench scale and bench impostors.
Scene sceneWithTrees(const Scene& full, const CameraPath& path, int trees);

}  // namespace forest::app
