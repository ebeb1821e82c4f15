// forest check: validates scene and camera-path files without rendering, and summarises them;
// --stats places the scene's trees (CPU only) and prints the vegetation statistics.
#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include <iostream>

#include "commands.hpp"
#include "forest/core/camera_path.hpp"
#include "forest/core/error.hpp"
#include "forest/core/scene.hpp"
#include "forest/terrain/terrain.hpp"
#include "forest/vegetation/forest.hpp"

namespace forest::app {
namespace {

struct CheckOptions {
  std::string scene;
  std::string path;
  bool stats = false;
  bool json = false;
};

// The vegetation statistics (vegetation::forestStats) of a scene, as JSON.
nlohmann::ordered_json vegetationStats(const Scene& scene) {
  const terrain::Terrain terrain(*scene.terrain);
  const vegetation::Forest forest(*scene.vegetation, terrain);
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
                              {"stems_per_ha_overall", s.terrainAreaHa > 0.0 ? s.trees / s.terrainAreaHa : 0.0}};
  return j;
}

void printStats(const nlohmann::ordered_json& j) {
  std::string species;
  for (const auto& [name, count] : j["species"].items())
    species += fmt::format("{}{} {} ({} young, {} mature, {} old)", species.empty() ? "" : "; ", count["trees"].get<int>(), name,
                           count["young"].get<int>(), count["mature"].get<int>(), count["old"].get<int>());
  std::cout << fmt::format("  trees: {} of {} requested ({}); {:.1f} ha of terrain, {:.1f} stems/ha overall\n", j["trees"].get<int>(),
                           j["requested"].get<int>(), species, j["terrain_area_ha"].get<double>(), j["stems_per_ha_overall"].get<double>());
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
  return [options] { return runCheck(*options); };
}

}  // namespace forest::app
