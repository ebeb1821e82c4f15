#pragma once
// The oracle of forest bench culling: per frame of a camera path, what has a pixel in a
// brute-force object-ID image — trees, props and tiles, and of the tiles the blocks
// (terrain::Terrain::blockBoxes at the frame's level; TerrainRenderer::Output::BlockId) — and
// the least a method that draws the previous frame's visible set untested draws above it.
#include <cstdint>
#include <functional>
#include <vector>

#include "forest/core/camera.hpp"
#include "forest/culling/bvh.hpp"
#include "forest/render/scene_objects.hpp"
#include "forest/terrain/terrain.hpp"

namespace forest::app {

struct VisibleSet {
  std::vector<std::uint32_t> objects;        // sorted: every object with a pixel, tiles included
  std::vector<std::uint32_t> notTerrain;     // the trees and props among them
  std::vector<terrain::TileBlock> blocks;    // the tiles' blocks with a pixel, sorted (tile, block)
  // Triangles of what had a pixel in the frame before, has none now and still meets the frustum
  // (trees, props and blocks at an unchanged level): what a method that draws the previous
  // frame's visible set untested (CHC, CHC++) draws above the oracle at the least.
  long long lagTriangles = 0;
  // The terrain triangles of `blocks`, and of the visible tiles drawn whole (every block of them
  // that meets the frustum, as the frame draws a tile without [culling] terrain_blocks).
  long long blockTriangles = 0, wholeTileTriangles = 0;
};

// The median over sets[from…] of the oracle's triangles (oracleTriangles[f], as drawn) with each
// visible tile drawn whole instead of by its visible blocks.
double wholeTileOracleTrianglesP50(const std::vector<VisibleSet>& sets, const std::vector<long long>& oracleTriangles, std::size_t from);

// The visible sets along `path`, rendered at width × height with the renderers' ID outputs (the
// terrain's: Output::BlockId, with IDs from blockIdBase on, past every object's). `progress`
// is called after each frame.
std::vector<VisibleSet> bruteForceVisibleSets(const render::SceneObjects& objects, const terrain::Terrain& terrain,
                                              const render::TerrainRenderer& terrainBlockIds, std::uint32_t blockIdBase,
                                              const render::TreeRenderer* treeIds, const render::PropRenderer* propIds,
                                              const culling::Bvh& bvh, const std::vector<Camera>& path, const SunSettings& sun,
                                              int width, int height, const std::function<void()>& progress);

// The oracle's frame: exactly the visible set, in two draws (trees and props, then the blocks).
long long drawVisibleSet(render::SceneDrawer& drawer, const VisibleSet& visible);

}  // namespace forest::app
