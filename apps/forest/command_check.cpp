// forest check: validates scene and camera-path files without rendering, and summarises them;
// --stats places the scene's trees (CPU only) and prints the vegetation statistics; --clearance
// checks every frame's camera of a path against the trees and props it would show.
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <iostream>

#include "commands.hpp"
#include "forest/core/camera_path.hpp"
#include "forest/core/error.hpp"
#include "forest/core/heap.hpp"
#include "forest/core/scene.hpp"
#include "forest/raytrace/clearance.hpp"
#include "forest/raytrace/scene_mirror.hpp"
#include "forest/terrain/terrain.hpp"
#include "forest/vegetation/forest.hpp"

namespace forest::app {
namespace {

struct CheckOptions {
  std::string scene;
  std::string path;
  bool stats = false;
  bool json = false;
  bool clearance = false;
  double fps = 30.0;
};

// Every frame of the path (at `fps`) against the trees (at the LOD and sway the renderer gives
// them) and the props: the eye outside them and nothing between it and the near plane
// (raytrace::cameraClearance). Prints the frames that are not clear; returns their count.
int checkClearance(const Scene& scene, const CameraPath& path, double fps) {
  const terrain::Terrain terrain(*scene.terrain);
  const vegetation::Forest forest(*scene.vegetation, terrain);
  const int frames = path.frameCount(fps);
  const auto treeCount = static_cast<std::uint32_t>(forest.trees().size());
  // Only a tree whose box (over all times) comes within the near distance plus the near
  // rectangle's half diagonal of the eye can hold the eye or cut the near plane (a million trees
  // are not mirrored for every frame).
  std::vector<Aabb> treeBoxes(treeCount);
  for (std::uint32_t t = 0; t < treeCount; ++t) treeBoxes[t] = forest.treeBounds(t);
  const Camera lens = scene.startCamera();
  const double halfHeight = lens.near * std::tan(0.5 * lens.fovy);
  const double reach = lens.near + std::hypot(halfHeight, halfHeight * scene.render.width / scene.render.height);
  std::vector<std::uint32_t> nearby;
  int blocked = 0;
  for (int f = 0; f < frames; ++f) {
    const double time = path.startTime() + f / fps;
    const CameraPose pose = path.at(time);
    Camera camera = scene.startCamera();
    camera.aspect = static_cast<double>(scene.render.width) / scene.render.height;
    camera.position = pose.position;
    if (path.aboveGround()) camera.position.y += terrain.heightAt(pose.position.x, pose.position.z);
    camera.yaw = glm::radians(pose.yaw_deg);
    camera.pitch = glm::radians(pose.pitch_deg);
    nearby.clear();
    for (std::uint32_t t = 0; t < treeCount; ++t)
      if (treeBoxes[t].distanceTo(camera.position) <= reach) nearby.push_back(t);
    raytrace::RayScene rays;
    raytrace::mirrorScene(rays, nullptr, nullptr, &forest, camera, {0, 0, treeCount, time, &scene.props, &nearby});
    const raytrace::Clearance c = raytrace::cameraClearance(rays, camera);
    if (c.clear) continue;
    if (++blocked <= 20) {
      std::string object = fmt::format("prop {}", c.objectId - treeCount);
      if (c.objectId < treeCount) {
        const vegetation::TreeInstance& tree = forest.trees()[c.objectId];
        object = fmt::format("tree {} ({} at x {:.1f}, z {:.1f})", c.objectId, vegetation::speciesName(tree.species), tree.position.x,
                             tree.position.z);
      }
      std::cout << fmt::format("  frame {} (t {:.2f} s, eye {:.1f} {:.1f} {:.1f}): {}: {}\n", f, time, camera.position.x,
                               camera.position.y, camera.position.z, c.what, object);
    }
  }
  std::cout << fmt::format("  clearance: {} of {} frames clear of trunks, crowns and props{}\n", frames - blocked, frames,
                           blocked > 20 ? fmt::format(" (the first 20 of {} others listed)", blocked) : "");
  return blocked;
}

// The vegetation statistics (vegetation::forestStats) of a scene, as JSON.
nlohmann::ordered_json vegetationStats(const Scene& scene) {
  const terrain::Terrain terrain(*scene.terrain);
  const double heapBefore = heapInUseMegabytes();
  const auto start = std::chrono::steady_clock::now();
  const vegetation::Forest forest(*scene.vegetation, terrain);
  const double placementSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double forestMib = heapInUseMegabytes() - heapBefore;
  const vegetation::ForestStats s = vegetation::forestStats(forest);
  // Per species: its trees, and how many of them in each size class.
  nlohmann::ordered_json species;
  for (int k = 0; k < vegetation::kSpeciesCount; ++k) {
    const auto& bySize = s.perSpeciesAndSize[static_cast<size_t>(k)];
    species[std::string(vegetation::speciesName(static_cast<vegetation::Species>(k)))] = {
        {"trees", s.perSpecies[static_cast<size_t>(k)]}, {"young", bySize[0]}, {"mature", bySize[1]}, {"old", bySize[2]}};
  }
  nlohmann::ordered_json j = {{"trees", s.trees},
                              {"requested", s.requested},
                              {"species", species},
                              {"terrain_area_ha", s.terrainAreaHa},
                              {"stands", forest.stands() != nullptr},
                              {"stand_area_ha", s.standAreaHa},
                              {"trees_in_stands", s.inStands},
                              {"share_in_stands", s.shareInStands},
                              {"stems_per_ha_in_stands", s.stemsPerHaInStands},
                              {"stems_per_ha_overall", s.terrainAreaHa > 0.0 ? s.trees / s.terrainAreaHa : 0.0},
                              {"placement_s", placementSeconds},
                              {"bytes_per_tree", s.trees > 0 ? forestMib * (1 << 20) / s.trees : 0.0}};
  return j;
}

void printStats(const nlohmann::ordered_json& j) {
  std::string species;
  for (const auto& [name, count] : j["species"].items())
    species += fmt::format("{}{} {} ({} young, {} mature, {} old)", species.empty() ? "" : "; ", count["trees"].get<int>(), name,
                           count["young"].get<int>(), count["mature"].get<int>(), count["old"].get<int>());
  std::cout << fmt::format("  trees: {} of {} requested ({}); {:.1f} ha of terrain, {:.1f} stems/ha overall\n", j["trees"].get<int>(),
                           j["requested"].get<int>(), species, j["terrain_area_ha"].get<double>(), j["stems_per_ha_overall"].get<double>());
  std::cout << fmt::format("  placed in {:.1f} s (species meshes, placement, clusters); {:.0f} bytes per tree on the CPU (the forest's heap; "
                           "the frame adds its boxes, query shapes, BVH and instance buffers: forest walkthrough reports the start-up)\n",
                           j["placement_s"].get<double>(), j["bytes_per_tree"].get<double>());
  if (!j["stands"].get<bool>()) {
    std::cout << "  stands: none (no [vegetation.stands]: trees spread evenly)\n";
    return;
  }
  std::cout << fmt::format("  stands: {:.1f} ha; {} trees in them ({:.1f}%), {:.0f} stems/ha in stands\n", j["stand_area_ha"].get<double>(),
                           j["trees_in_stands"].get<int>(), 100.0 * j["share_in_stands"].get<double>(),
                           j["stems_per_ha_in_stands"].get<double>());
}

int runCheck(const CheckOptions& options) {
  if (options.scene.empty() && options.path.empty()) throw InputError("check: give --scene FILE and/or --path FILE");
  if (options.stats && options.scene.empty()) throw InputError("check --stats: give --scene FILE");
  if (options.json && !options.stats) throw InputError("check --json: prints the --stats; give --stats too");
  if (options.clearance && (options.scene.empty() || options.path.empty()))
    throw InputError("check --clearance: give --scene FILE and --path FILE");
  if (options.stats) {
    const Scene scene = loadScene(options.scene);
    if (!scene.terrain || !scene.vegetation) throw InputError(options.scene + ": --stats needs a scene with [terrain] and [vegetation]");
    const nlohmann::ordered_json stats = vegetationStats(scene);
    if (options.json) {
      std::cout << stats.dump(2) << "\n";
      return 0;
    }
    std::cout << options.scene << ": ok\n";
    printStats(stats);
  } else if (!options.scene.empty()) {
    const Scene scene = loadScene(options.scene);
    std::cout << fmt::format("{}: ok — {}x{}, fovy {}°, near {}, far {}, {} props\n", options.scene,
                             scene.render.width, scene.render.height, scene.camera.fovy_deg, scene.camera.near,
                             scene.camera.far, scene.props.size());
  }
  if (!options.path.empty()) {
    const CameraPath path = CameraPath::load(options.path);
    std::cout << fmt::format("{}: ok — {} keys, t = {} … {} s\n", options.path, path.keys().size(),
                             path.startTime(), path.endTime());
    if (options.clearance) {
      const Scene scene = loadScene(options.scene);
      if (!scene.terrain || !scene.vegetation) throw InputError(options.scene + ": --clearance needs a scene with [terrain] and [vegetation]");
      if (path.aboveGround() && !scene.terrain) throw InputError(options.path + ": heights = \"above_ground\" needs a scene with [terrain]");
      return checkClearance(scene, path, options.fps) == 0 ? 0 : 1;
    }
  }
  return 0;
}

}  // namespace

Run addCheckCommand(CLI::App& app) {
  auto options = std::make_shared<CheckOptions>();
  CLI::App* command = app.add_subcommand("check", "Validate scene and camera-path files (no rendering)");
  command->add_option("--scene", options->scene, "Scene file (TOML)");
  command->add_option("--path", options->path, "Camera-path file (TOML)");
  command->add_flag("--stats", options->stats,
                    "Place the scene's trees (no rendering) and print the vegetation statistics: trees per species,\n"
                    "stand area, share of trees in stands, stems per hectare in them");
  command->add_flag("--json", options->json, "With --stats: print them as JSON");
  command->add_flag("--clearance", options->clearance,
                    "With --scene and --path: check every frame's camera against the trees and props (ray traced): the\n"
                    "eye outside them and nothing between it and the near plane; exit 1 naming the frames that fail");
  command->add_option("--fps", options->fps, "With --clearance: frames per second of path time (0.1 to 1000)")
      ->check(CLI::Range(0.1, 1000.0))
      ->capture_default_str();
  return [options] { return runCheck(*options); };
}

}  // namespace forest::app
