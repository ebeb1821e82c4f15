#pragma once
// Visibility of the terrain by block inside the tiles the culler draws. A tile is one culling
// object: found visible, it would draw every block in the frustum — 8192 triangles at level 0 —
// when one corner of it shows between the trunks. This unit keeps, per block of a tile at its
// level (terrain::Terrain::blockBoxes: 16, 4 or 1 per tile), whether the block was visible. Its
// queries draw the block's own triangles (TerrainRenderer::drawBlockQueries: a box sees over the
// crest in front of it where the surface does not):
//   - a block found visible is drawn with its tile during the traversal (so it occludes what is
//     queried after it), and every n_av frames it is queried again after the traversal (CHC's
//     assumption of coherence, Bittner et al. 2004, one level lower) with GL_GEQUAL, so that where
//     its own surface is still the nearest it passes; one hidden by nearer trees or terrain fails
//     and is hidden from the next frame on;
//   - a block found hidden is held back while its tile is drawn and asked on its own (a query
//     draws its block's triangles, so CHC++'s multiqueries, §3.4, would save no work here, and a
//     multiquery that saw a sample would draw every block in it): with chc++, in the batch of
//     queries that follows the tile's draw (issueDuring), and one that passes is drawn as soon
//     as that batch's results are in (takeDuring), before the traversal's next queries, then
//     asked again after the traversal like a drawn block; held by the traversal's last draw (or
//     with another strategy), after the traversal, drawn then (drawLate);
//   - a block not known yet — its tile was not drawn the frame before — is drawn with its tile
//     (as the whole tile was before: it occludes during the traversal) and asked after.
// The queries go out with batches the culler makes anyway (culling::QueriesAfterTraversal:
// answered by waits it makes anyway); a block whose box holds the eye or meets the near slab
// counts as visible without one. Asking the held blocks only after the traversal let a block
// that came into view — the ground in front of the walker, hidden the frame before by a tree
// beside the path — be drawn after every query behind it had passed: along the thesis walk at
// 10 201 trees, one such frame drew 132 k triangles for the exactly visible set's 8.4 k.
// With the last image's record (setShownInLastImage; [culling] image_visibility) a block drawn the
// frame before is visible exactly when it had a pixel then, and is not asked again while it has.
// Exact as the culler is: a block is either drawn during the traversal or drawn when its
// triangles passed the depth test against everything else drawn — a subset of what brute force
// draws in front of them. When a tile's level changes, its blocks take the visibility of the
// blocks they overlap at the old level (levels 0–3 share their 16 blocks; a coarser block is
// known when all the finer ones in it are).
#include <cstdint>
#include <span>
#include <vector>

#include "forest/culling/occlusion_culler.hpp"
#include "forest/terrain/terrain.hpp"

namespace forest::render {

class SceneDrawer;

class TerrainBlockVisibility final : public culling::QueriesAfterTraversal {
 public:
  // requeryFrames: n_av, ≥ 1 (CullingSettings::visible_requery_frames).
  TerrainBlockVisibility(const terrain::Terrain& terrain, int requeryFrames);

  // A new frame, drawn by `drawer` (the SceneDrawer the cull draws with): nothing is held.
  void beginFrame(SceneDrawer& drawer);
  // Which blocks had a pixel in the image of the frame before (render::ImageVisibility): per
  // tile, bit b for block b of the 4 × 4 at levels 0–3 (a coarser level's block has a pixel when
  // one of the blocks it covers has). For the next frame only (until drawLate); empty (the
  // default): not known.
  // A block drawn in that frame then counts as visible exactly when it showed, and no visible
  // block of such a tile is asked again (the image answers what n_av's re-query asks).
  void setShownInLastImage(std::span<const std::uint16_t> shownBlocks) { shownInLastImage_ = shownBlocks; }
  // Forgets every block's visibility (a camera cut): each tile starts again with its blocks not known.
  void reset();
  // A frame drawn without it (frustum culling — culling::QueryPayoff's fallback — or a frozen
  // set: whole tiles): what it knew is stale, as after reset().
  void skipFrame() { reset(); }
  // Whether block `block` of `tile`, drawn at `level` and meeting the frustum, is drawn now (it
  // was visible or is not known); if not (it was hidden), it is held until issue() asks it. After
  // issue() (a tile drawn after the traversal's last queries: chc++'s late leaves) always.
  bool drawNow(int tile, int level, int block);
  // Handed to OcclusionCuller::cull, which calls it after its traversal's last draw: queries the
  // held blocks not asked yet, the visible ones due and those drawn by takeDuring, in the
  // culler's last batch.
  void issue(culling::OcclusionCuller& culler) override;
  // Every block at most twice: held and asked during the traversal, then asked again at its end.
  std::size_t maxQueries() const override { return 2 * nextQuery_.size(); }
  // chc++, during its traversal: asks the blocks held back since the last call, with the batch of
  // queries that follows (issueDuring); once their results are in, draws those found visible
  // (takeDuring) — they are asked again after the traversal, with their triangles.
  bool issueDuring(culling::OcclusionCuller& culler) override;
  long long takeDuring(culling::OcclusionCuller& culler) override;
  // After the cull: takes issue()'s results and draws the held blocks found visible
  // (SceneDrawer::drawTerrainBlocks). Returns the triangles drawn.
  long long drawLate(culling::OcclusionCuller& culler);

  // A tile's bits mapped from level `from` to level `to`: a block is visible when a block of the
  // other level overlapping it was (any), known when all of those were (all).
  enum class Combine { Any, All };
  static std::uint16_t mapLevel(std::uint16_t bits, int from, int to, Combine combine);

  struct Stats {
    int drawnInTraversal = 0;  // blocks drawn by drawNow
    int held = 0;              // blocks held back
    int requeried = 0;         // blocks drawn by drawNow that issue queries (not known, or due)
    int drawnDuring = 0;       // held blocks found visible during the traversal and drawn by takeDuring
    int drawnAfter = 0;        // held blocks found visible after it and drawn by drawLate
  };
  const Stats& stats() const { return stats_; }  // this frame's

 private:
  struct TileState {
    int level = -1;               // the level the bits below are of (-1: none yet)
    std::uint16_t known = 0;      // bit b: block b has been queried
    std::uint16_t visible = 0;    // bit b: block b was visible at its last query
    std::uint64_t drawn = 0;      // the last frame the tile was drawn in
    std::uint16_t drawnBlocks = 0;  // bit b: block b was drawn in that frame (at `level`)
    bool fromImage = false;         // this frame's bits of the blocks drawn the frame before come from its image
  };
  struct Held {  // a block held back, or one drawn already whose visibility is asked
    int tile, level, block;
    enum Kind { Hidden, Drawn } kind;
    bool asked = false;  // its query went out during the traversal (issue() leaves it out)
  };
  // Issues queries for held_[asking_[…]] (the current batch).
  void ask(culling::OcclusionCuller& culler);
  // Takes the current batch's results into the blocks' bits; the held-back blocks found visible
  // go to late_ (and become Drawn, asked again by issue()).
  void takeResults(culling::OcclusionCuller& culler);
  std::size_t slot(int tile, int block) const { return static_cast<std::size_t>(tile) * kBlocks + static_cast<std::size_t>(block); }

  static constexpr int kBlocks = terrain::Terrain::kMaxBlockBoxes;
  static_assert(kBlocks <= 16, "a tile's blocks are the bits of a 16-bit mask");
  const terrain::Terrain& terrain_;
  int requeryFrames_;
  std::uint64_t frame_ = 0;
  SceneDrawer* drawer_ = nullptr;  // this frame's (beginFrame)
  bool issued_ = false;            // this frame's queries went out: drawLate takes their results
  bool traversalEnded_ = false;    // issue() was called: a tile drawn after it draws every block asked for
  std::vector<TileState> tiles_;
  std::vector<std::uint64_t> nextQuery_;  // per (tile, block): a visible block is asked again from this frame
  std::vector<std::uint64_t> heldIn_;     // per (tile, block): the frame it was last held (held once a frame)
  // Per (tile, block): how it is asked when held back — by its box, or (its box saw past what hid
  // it: found visible by the box, then hidden by its triangles) by its triangles.
  enum class QueryBy : std::uint8_t { Box, BoxPassed, Surface };
  std::vector<QueryBy> queryBy_;
  std::vector<std::uint8_t> bySurface_;  // per held block this frame: asked with its triangles
  std::vector<Held> held_;
  std::vector<std::size_t> asking_;  // the held_ entries of the batch in flight
  std::size_t duringFrom_ = 0;       // held_ entries from this one on were held after the last issueDuring
  std::vector<Aabb> boxes_;
  std::vector<std::uint32_t> groupEnds_;
  std::vector<terrain::TileBlock> late_, queryBlocks_;
  Stats stats_;
  std::span<const std::uint16_t> shownInLastImage_;  // setShownInLastImage's, for one frame
};

}  // namespace forest::render
