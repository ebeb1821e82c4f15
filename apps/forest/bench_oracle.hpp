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
  // The trees and props of the frame before's set that its samples, moved into this frame's view,
  // guess hidden (culling::ReprojectedImage, as the frame's render::ImageVisibility samples its
  // read-back: ReprojectedImage::kSampleStride). Sorted.
  std::vector<std::uint32_t> hiddenByReprojection;
};

// The median over sets[from…] of the oracle's triangles (oracleTriangles[f], as drawn) with each
// visible tile drawn whole instead of by its visible blocks.
double wholeTileOracleTrianglesP50(const std::vector<VisibleSet>& sets, const std::vector<long long>& oracleTriangles, std::size_t from);

// The visible sets along `path`, rendered at width × height with the renderers' ID outputs (the
// terrain's: Output::BlockId, with IDs from blockIdBase on, past every object's). `progress`
// is called after each frame. `guessHidden`: fill VisibleSet::hiddenByReprojection.
std::vector<VisibleSet> bruteForceVisibleSets(const render::SceneObjects& objects, const terrain::Terrain& terrain,
                                              const render::TerrainRenderer& terrainBlockIds, std::uint32_t blockIdBase,
                                              const render::TreeRenderer* treeIds, const render::PropRenderer* propIds,
                                              const culling::Bvh& bvh, const std::vector<Camera>& path, const SunSettings& sun,
                                              int width, int height, bool guessHidden, const std::function<void()>& progress);

// What the frame's lighting pass records of frame f's image for the next frame's culling
// ([culling] image_visibility; render/src/image_visibility.hpp): the objects of its visible set,
// and per tile its blocks as the 4 × 4 of levels 0–3 — the frame's image is brute force's
// (exactness), so the record is the oracle's set. `objects`, `tiles`: the scene's counts.
struct ShownRecord {
  std::vector<std::uint8_t> objects;   // OcclusionCuller::setShownInLastImage
  std::vector<std::uint16_t> blocks;   // TerrainBlockVisibility::setShownInLastImage
};
void recordShown(const VisibleSet& visible, std::size_t objects, std::size_t tiles, ShownRecord& out);
// With [culling] image_reprojection: the record's objects less those `now` guesses hidden.
void clearHiddenByReprojection(const VisibleSet& now, ShownRecord& record);

// The oracle's frame: exactly the visible set, in two draws (trees and props, then the blocks).
long long drawVisibleSet(render::SceneDrawer& drawer, const VisibleSet& visible);

// The share of the oracle's triangles over frames [max(1, from), …) that its one-frame lag draws
// (VisibleSet::lagTriangles; oracleTriangles[f]: the oracle's frame f as drawn).
double oracleLagShare(const std::vector<VisibleSet>& sets, const std::vector<long long>& oracleTriangles, std::size_t from);

// What a strategy drew of the trees and props, per frame on average, sorted by the oracle's
// visible sets of that frame (V_f) and the one before (V_f-1):
//   visible — in V_f;
//   lag     — not in V_f, in V_f-1: the one-frame lag (the least a CHC-type method draws above V_f);
//   carried — in neither, and drawn by the strategy the frame before as well: kept drawn by
//             coherence (CHC++'s n_av frames without a query) or found visible again;
//   fresh   — in neither, not drawn the frame before: a query that passed this frame although
//             the finished image hides the object (its depth then lacked nearer objects).
struct DrawnBreakdown {
  double visible = 0.0, lag = 0.0, carried = 0.0, fresh = 0.0;
};

// The oracle's own trees and props per frame on average over frames [max(1, from), …): visible
// (|V_f|) and lag (|V_f-1 \ V_f|, in the frustum or not); carried and fresh stay 0.
DrawnBreakdown oracleTreesAndProps(const std::vector<VisibleSet>& sets, std::size_t from);

// Forwards a culler's draws to the frame's drawer and records the trees and props among them.
class DrawnRecorder : public culling::ObjectDrawer {
 public:
  explicit DrawnRecorder(const render::SceneObjects& objects) : objects_(objects) {}
  // Frame f: draws go to `drawer` until endFrame.
  void beginFrame(render::SceneDrawer& drawer);
  // Sorts frame f's draws against the oracle's sets (`before`: V_f-1, null for the first frame),
  // counted in the breakdown when `measured`.
  void endFrame(const VisibleSet& now, const VisibleSet* before, bool measured);
  DrawnBreakdown meanPerFrame() const;

  long long draw(std::span<const std::uint32_t> objects) override;
  bool queriesOwnGeometry(std::uint32_t object, culling::QueryGeometry geometry) const override {
    return drawer_->queriesOwnGeometry(object, geometry);
  }
  long long drawGeometryQueries(std::span<const std::uint32_t> objects, std::span<const std::uint32_t> slots,
                                culling::QueryGeometry geometry) override {
    return drawer_->drawGeometryQueries(objects, slots, geometry);
  }

 private:
  const render::SceneObjects& objects_;
  render::SceneDrawer* drawer_ = nullptr;
  std::vector<std::uint32_t> drawn_, drawnBefore_;  // trees and props; sorted once the frame ends
  DrawnBreakdown sum_;
  int frames_ = 0;
};

}  // namespace forest::app
