#include "forest/render/terrain_block_visibility.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "forest/core/error.hpp"
#include "forest/render/scene_objects.hpp"

namespace forest::render {

TerrainBlockVisibility::TerrainBlockVisibility(const terrain::Terrain& terrain, int requeryFrames)
    : terrain_(terrain),
      requeryFrames_(requeryFrames),
      tiles_(static_cast<std::size_t>(terrain.tileCount())),
      nextQuery_(tiles_.size() * kBlocks, 0),
      heldIn_(tiles_.size() * kBlocks, 0),
      queryBy_(tiles_.size() * kBlocks, QueryBy::Box) {
  if (requeryFrames < 1) throw Error(fmt::format("TerrainBlockVisibility: n_av = {}, expected at least 1", requeryFrames));
  held_.reserve(nextQuery_.size());
  asking_.reserve(nextQuery_.size());
  boxes_.reserve(nextQuery_.size());
  groupEnds_.reserve(nextQuery_.size());
  late_.reserve(nextQuery_.size());
  queryBlocks_.reserve(nextQuery_.size());
  bySurface_.reserve(nextQuery_.size());
}

void TerrainBlockVisibility::beginFrame(SceneDrawer& drawer) {
  ++frame_;
  held_.clear();
  asking_.clear();
  duringFrom_ = 0;
  stats_ = Stats{};
  drawer_ = &drawer;
  issued_ = traversalEnded_ = false;
}

void TerrainBlockVisibility::reset() {
  std::fill(tiles_.begin(), tiles_.end(), TileState{});
  std::fill(queryBy_.begin(), queryBy_.end(), QueryBy::Box);
}

bool TerrainBlockVisibility::drawNow(int tile, int level, int block) {
  if (tile < 0 || tile >= static_cast<int>(tiles_.size()) || block < 0 || block >= terrain::blocksPerTile(level))
    throw Error(fmt::format("TerrainBlockVisibility: block {} of tile {} at level {} does not exist", block, tile, level));
  TileState& t = tiles_[static_cast<std::size_t>(tile)];
  if (t.drawn != frame_) {  // the tile's first block this frame
    t.fromImage = false;
    if (t.drawn + 1 != frame_) {
      t.known = 0;  // not drawn the frame before: what it knew is stale
    } else if (static_cast<std::size_t>(tile) < shownInLastImage_.size()) {
      // The blocks drawn the frame before are visible exactly when they showed in its image.
      const std::uint16_t shown = mapLevel(shownInLastImage_[static_cast<std::size_t>(tile)], 0, t.level, Combine::Any);
      t.visible = static_cast<std::uint16_t>((t.visible & ~t.drawnBlocks) | (t.drawnBlocks & shown));
      t.known = static_cast<std::uint16_t>(t.known | t.drawnBlocks);
      t.fromImage = true;
    }
    t.drawnBlocks = 0;
    t.drawn = frame_;
  }
  if (t.level != level) {
    if (t.level >= 0) {
      t.visible = mapLevel(t.visible, t.level, level, Combine::Any);
      t.known = mapLevel(t.known, t.level, level, Combine::All);
    }
    t.level = level;
  }
  if (traversalEnded_) {  // a tile drawn after the last queries went out (chc++'s late leaves): whole
    t.drawnBlocks = static_cast<std::uint16_t>(t.drawnBlocks | 1u << block);
    ++stats_.drawnInTraversal;
    return true;
  }
  const std::size_t s = slot(tile, block);
  const bool listed = heldIn_[s] == frame_;
  heldIn_[s] = frame_;
  const bool known = (t.known >> block & 1u) != 0, visible = (t.visible >> block & 1u) != 0;
  if (!known || visible) {
    ++stats_.drawnInTraversal;
    t.drawnBlocks = static_cast<std::uint16_t>(t.drawnBlocks | 1u << block);
    if ((!known || (!t.fromImage && nextQuery_[s] <= frame_)) && !listed) {
      held_.push_back({tile, level, block, Held::Drawn});
      ++stats_.requeried;
    }
    return true;
  }
  if (!listed) {
    held_.push_back({tile, level, block, Held::Hidden});
    ++stats_.held;
  }
  return false;
}

namespace {
constexpr int perSide = terrain::kTileQuads / 16;  // blocks per tile side at levels 0–3
}  // namespace

std::uint16_t TerrainBlockVisibility::mapLevel(std::uint16_t bits, int from, int to, Combine combine) {
  // Through the 4 × 4 blocks of levels 0–3: a block of blockQuads(level) quads spans
  // blockQuads / 16 of them per side.
  const auto blockOf = [](int region, int level) {
    const int span = std::min(terrain::blockQuads(level) / 16, perSide);
    const int blocks = perSide / span;
    return (region / perSide / span) * blocks + (region % perSide) / span;
  };
  std::uint16_t any = 0, missing = 0;
  for (int r = 0; r < perSide * perSide; ++r) {
    const bool set = (bits >> blockOf(r, from) & 1u) != 0;
    const auto bit = static_cast<std::uint16_t>(1u << blockOf(r, to));
    if (set) any = static_cast<std::uint16_t>(any | bit);
    else missing = static_cast<std::uint16_t>(missing | bit);
  }
  return combine == Combine::Any ? any : static_cast<std::uint16_t>(any & ~missing);
}

void TerrainBlockVisibility::issue(culling::OcclusionCuller& culler) {
  if (!drawer_) throw Error("TerrainBlockVisibility::issue: no frame begun");
  traversalEnded_ = true;
  asking_.clear();
  for (std::size_t i = 0; i < held_.size(); ++i)
    if (!held_[i].asked) asking_.push_back(i);
  if (asking_.empty()) return;
  ask(culler);
  issued_ = true;
}

bool TerrainBlockVisibility::issueDuring(culling::OcclusionCuller& culler) {
  if (!drawer_) throw Error("TerrainBlockVisibility::issueDuring: no frame begun");
  // Only the blocks held back: a drawn block's query asks whether it is hidden, which only the
  // finished depth answers.
  asking_.clear();
  for (std::size_t i = duringFrom_; i < held_.size(); ++i)
    if (held_[i].kind == Held::Hidden) asking_.push_back(i);
  duringFrom_ = held_.size();
  if (asking_.empty()) return false;
  ask(culler);
  // One found hidden now is hidden after the traversal too (the depth only gets nearer).
  for (std::size_t i : asking_) held_[i].asked = true;
  return true;
}

long long TerrainBlockVisibility::takeDuring(culling::OcclusionCuller& culler) {
  takeResults(culler);
  stats_.drawnDuring += static_cast<int>(late_.size());
  return late_.empty() ? 0 : drawer_->drawTerrainBlocks(late_);
}

void TerrainBlockVisibility::ask(culling::OcclusionCuller& culler) {
  // One query per block: a query drawn with the block's triangles costs them whether it asks
  // for one block or several, and a multiquery that saw a sample would draw every block in it.
  // A block held back is asked with its box (12 triangles) unless its box has seen past what hid
  // it before; a drawn block (due, or not known) with its own triangles, GL_GEQUAL — its box
  // would pass in front of its own surface.
  boxes_.clear();
  groupEnds_.clear();
  bySurface_.clear();
  for (std::size_t i : asking_) {
    const Held& h = held_[i];
    boxes_.push_back(terrain_.blockBoxes(h.tile, h.level)[static_cast<std::size_t>(h.block)]);
    groupEnds_.push_back(static_cast<std::uint32_t>(boxes_.size()));
    bySurface_.push_back(h.kind == Held::Drawn || queryBy_[slot(h.tile, h.block)] == QueryBy::Surface ? 1 : 0);
  }
  // Surfaces: a box sees over the crest in front of it and between trunks where the surface does not.
  SceneDrawer& drawer = *drawer_;
  const auto surfaces = [this, &drawer](std::span<const std::uint32_t> groups, std::span<const std::uint32_t> slots) {
    queryBlocks_.clear();
    for (const std::uint32_t g : groups) {
      const Held& h = held_[asking_[g]];
      queryBlocks_.push_back({h.tile, h.level, h.block});
    }
    return drawer.drawTerrainBlockQueries(queryBlocks_, slots);
  };
  culler.issueAfterCull(boxes_, groupEnds_, surfaces, bySurface_);
}

void TerrainBlockVisibility::takeResults(culling::OcclusionCuller& culler) {
  const std::vector<bool>& visible = culler.afterCullResults();
  late_.clear();
  for (std::size_t k = 0; k < asking_.size(); ++k) {
    Held& h = held_[asking_[k]];
    TileState& t = tiles_[static_cast<std::size_t>(h.tile)];
    const auto bit = static_cast<std::uint16_t>(1u << h.block);
    const std::size_t s = slot(h.tile, h.block);
    t.known = static_cast<std::uint16_t>(t.known | bit);
    if (visible[k]) {
      t.visible = static_cast<std::uint16_t>(t.visible | bit);
      if (bySurface_[k] != 0) {
        // Asked again in n_av frames (CHC's assumption of coherence).
        nextQuery_[s] = frame_ + static_cast<std::uint64_t>(requeryFrames_);
        queryBy_[s] = QueryBy::Box;
      } else {
        // Its box saw a sample: drawn now, and asked with its triangles next frame.
        nextQuery_[s] = frame_ + 1;
        queryBy_[s] = QueryBy::BoxPassed;
      }
      if (h.kind != Held::Drawn) {
        late_.push_back({h.tile, h.level, h.block});
        t.drawnBlocks = static_cast<std::uint16_t>(t.drawnBlocks | bit);
        // Drawn now; found during the traversal, it is asked again after it (issue()).
        h.kind = Held::Drawn;
        h.asked = false;
      }
    } else {
      t.visible = static_cast<std::uint16_t>(t.visible & ~bit);
      // Hidden by its triangles right after its box passed: the box sees past what hides it.
      if (queryBy_[s] == QueryBy::BoxPassed) queryBy_[s] = QueryBy::Surface;
    }
  }
}

long long TerrainBlockVisibility::drawLate(culling::OcclusionCuller& culler) {
  shownInLastImage_ = {};  // one frame's
  if (!issued_) return 0;  // nothing held
  issued_ = false;
  takeResults(culler);
  stats_.drawnAfter = static_cast<int>(late_.size());
  return late_.empty() ? 0 : drawer_->drawTerrainBlocks(late_);
}

}  // namespace forest::render
