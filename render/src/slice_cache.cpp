#include "slice_cache.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <tuple>

#include "forest/shadows/kept_slices.hpp"

namespace forest::render {
namespace {

auto blockKey(const terrain::TileBlock& b) { return std::tuple(b.tile, b.level, b.block, b.cells.first, b.cells.end); }

bool sameTarget(const LayerTarget& a, const LayerTarget& b) {
  return a.map == b.map && a.side == b.side && a.size == b.size && a.layers == b.layers && a.slopeScaleBias == b.slopeScaleBias && a.backside == b.backside;
}

bool contains(const shadows::TexelRect& outer, const shadows::TexelRect& inner) {
  return inner.empty() || (outer.x0 <= inner.x0 && outer.y0 <= inner.y0 && inner.x1 <= outer.x1 && inner.y1 <= outer.y1);
}

// `read` grown by kRectMarginShare of the map per side, inside the layer.
shadows::TexelRect grown(const shadows::TexelRect& read, int size) {
  if (read.empty()) return read;
  const int margin = static_cast<int>(std::ceil(kRectMarginShare * size));
  return {std::max(read.x0 - margin, 0), std::max(read.y0 - margin, 0), std::min(read.x1 + margin, size), std::min(read.y1 + margin, size)};
}

}  // namespace

SliceCache::SliceCache(const SceneObjects& objects, const terrain::Terrain* terrain, const vegetation::Forest* forest)
    : objects_(objects), terrain_(terrain), forest_(forest), tallestTree_(forest ? forest->tallestTree() : 0.0) {}

bool SliceCache::blockBefore(const DrawnBlock& a, const DrawnBlock& b) { return blockKey(a.block) < blockKey(b.block); }

void SliceCache::forget() {
  for (Layer& layer : layers_) layer.valid = false;
}

void SliceCache::forget(int layer) { layers_.at(static_cast<size_t>(layer)).valid = false; }

bool SliceCache::sameMatrices(const Layer& layer, const ShadowSlice& slice) {
  const shadows::ShadowSetup& now = slice.setup;
  return layer.worldToShadowClip == now.worldToShadowClip && layer.linearDepth == now.linearDepth &&
         (!now.linearDepth || layer.worldToLightDepth == now.worldToLightDepth) && layer.terrainByBlock == slice.terrainByBlock;
}

void SliceCache::blocksOf(bool byBlock, std::span<const terrain::TileBlock> blocks, std::span<const std::uint32_t> casters,
                          const terrain::TerrainLod* lod, std::vector<DrawnBlock>& out) const {
  out.clear();
  if (!terrain_ || !lod) return;
  auto drawnNow = [&](const terrain::TileBlock& b) { return DrawnBlock{b, terrain_->blockMorph(b.tile, b.level, b.block, *lod), lod->eye}; };
  if (byBlock) {
    for (const terrain::TileBlock& b : blocks) out.push_back(drawnNow(b));
  } else {  // tiles drawn whole: every block of each at its level
    for (std::uint32_t o : casters) {
      const SceneObjects::Object& object = objects_.objects()[o];
      if (object.kind != SceneObjects::Kind::Tile) continue;
      const int tile = static_cast<int>(object.index), level = terrain_->tileLevel(tile, *lod);
      const int count = static_cast<int>(terrain_->blockBoxes(tile, level).size());
      for (int b = 0; b < count; ++b) out.push_back(drawnNow(terrain::TileBlock{tile, level, b, {}}));
    }
  }
  std::sort(out.begin(), out.end(), blockBefore);
}

void SliceCache::current(const ShadowSlice& slice, const terrain::TerrainLod* lod) {
  casters_.assign(slice.casters.begin(), slice.casters.end());
  std::sort(casters_.begin(), casters_.end());
  blocksOf(slice.terrainByBlock, slice.terrainBlocks, casters_, lod, blocks_);
}

std::string_view SliceCache::whyHeldChanged(const Layer& layer, const ShadowSlice& slice, const DrawView& eye, const glm::dvec3& l) const {
  bool treesHeld = false;
  auto at = layer.casters.begin();
  for (std::uint32_t o : casters_) {  // both increasing: one walk through the held casters
    at = std::lower_bound(at, layer.casters.end(), o);
    if (at == layer.casters.end() || *at != o) continue;  // not held: added, at this frame's LOD
    const SceneObjects::Object& object = objects_.objects()[o];
    if (object.kind != SceneObjects::Kind::Tree || !forest_) continue;
    treesHeld = true;
    if (forest_->lodFor(object.index, eye.lodEye) != layer.treeLods[static_cast<size_t>(at - layer.casters.begin())]) return "lod";
  }
  for (const DrawnBlock& now : blocks_) {
    // The tile held at the same level only (two levels of one surface in a layer would shadow each
    // other), its blocks unmorphed or fully morphed both then and now (a vertex in a ramp moves
    // with the eye). A tile drawn whole must be held whole.
    const auto first = std::lower_bound(layer.blocks.begin(), layer.blocks.end(), now.block.tile,
                                         [](const DrawnBlock& b, int tile) { return b.block.tile < tile; });
    bool held = false;
    for (auto it = first; it != layer.blocks.end() && it->block.tile == now.block.tile; ++it) {
      if (it->block.level != now.block.level) return "terrain";
      if (blockKey(it->block) != blockKey(now.block)) continue;
      held = true;
      if (it->morph != now.morph) return "terrain";
      if (now.morph == terrain::BlockMorph::Morphing && it->eye != now.eye) return "terrain";
    }
    if (!held && !slice.terrainByBlock && first != layer.blocks.end() && first->block.tile == now.block.tile) return "terrain";
  }
  if (treesHeld && tallestTree_ > 0.0) {
    // The farthest a tree point can have swayed since the clear, against the layer's finest texel.
    const double swayed = vegetation::windShearChangeBound(forest_->settings(), eye.time - layer.time) * tallestTree_;
    if (swayed > 0.0 && !(swayed <= shadows::finestTexelSide(slice.setup, layer.target.size, slice.setup.body.vertices(), l)))
      return "wind";
  }
  return "";
}

LayerDraw SliceCache::redraw(std::string_view why, const shadows::TexelRect& read, int size) {
  toDraw_ = casters_;
  blocksToDraw_.clear();
  for (const DrawnBlock& b : blocks_) blocksToDraw_.push_back(b.block);
  return {SliceUpdate::Redraw, why, "", toDraw_, blocksToDraw_, grown(read, size)};
}

LayerDraw SliceCache::plan(int index, const LayerTarget& target, const ShadowSlice& slice, const shadows::TexelRect& read,
                           const DrawView& eye, const terrain::TerrainLod* lod, const glm::dvec3& l, int staleFrames) {
  Layer& layer = layers_.at(static_cast<size_t>(index));
  ++layer.age;
  current(slice, lod);
  if (!layer.valid) return redraw("first", read, target.size);
  if (!sameTarget(layer.target, target)) return redraw("map", read, target.size);
  if (!sameMatrices(layer, slice)) return redraw("matrices", read, target.size);
  if (lod && (lod->morphStart != layer.lod.morphStart || lod->morphEnd != layer.lod.morphEnd)) return redraw("terrain", read, target.size);
  const std::string_view changed = whyHeldChanged(layer, slice, eye, l);
  if (!changed.empty() && layer.age > staleFrames) return redraw(changed, read, target.size);
  if (!contains(layer.rect, read)) return redraw("texels", read, target.size);
  // What it lacks, drawn into it.
  toDraw_.clear();
  std::set_difference(casters_.begin(), casters_.end(), layer.casters.begin(), layer.casters.end(), std::back_inserter(toDraw_));
  blocksToDraw_.clear();
  if (slice.terrainByBlock) {
    scratch_.clear();
    std::set_difference(blocks_.begin(), blocks_.end(), layer.blocks.begin(), layer.blocks.end(), std::back_inserter(scratch_), blockBefore);
    for (const DrawnBlock& b : scratch_) blocksToDraw_.push_back(b.block);
  }
  if (toDraw_.empty() && blocksToDraw_.empty()) return {SliceUpdate::Reuse, "", changed, {}, {}, layer.rect};
  return {SliceUpdate::Add, "casters", changed, toDraw_, blocksToDraw_, layer.rect};
}

void SliceCache::drawn(int index, const LayerTarget& target, const LayerDraw& d, const ShadowSlice& slice, const DrawView& eye,
                       const terrain::TerrainLod* lod) {
  Layer& layer = layers_.at(static_cast<size_t>(index));
  if (d.update == SliceUpdate::Reuse) return;
  auto lodOf = [&](std::uint32_t o) -> std::uint8_t {
    const SceneObjects::Object& object = objects_.objects()[o];
    return object.kind == SceneObjects::Kind::Tree && forest_ ? static_cast<std::uint8_t>(forest_->lodFor(object.index, eye.lodEye)) : 0;
  };
  // The blocks drawn now with their morph now (a tile drawn whole: all its blocks).
  blocksOf(slice.terrainByBlock, d.blocks, d.casters, lod, scratch_);
  if (d.update == SliceUpdate::Redraw) {
    layer.valid = true;
    layer.target = target;
    layer.rect = d.rect;
    layer.worldToShadowClip = slice.setup.worldToShadowClip;
    layer.worldToLightDepth = slice.setup.worldToLightDepth;
    layer.linearDepth = slice.setup.linearDepth;
    layer.terrainByBlock = slice.terrainByBlock;
    layer.time = eye.time;
    layer.age = 0;
    if (lod) layer.lod = *lod;
    layer.casters.assign(d.casters.begin(), d.casters.end());
    layer.treeLods.clear();
    for (std::uint32_t o : layer.casters) layer.treeLods.push_back(lodOf(o));
    std::swap(layer.blocks, scratch_);
    return;
  }
  // An addition: merge what was drawn into what it holds (both increasing, disjoint).
  mergedCasters_.clear();
  mergedLods_.clear();
  size_t i = 0, j = 0;
  while (i < layer.casters.size() || j < d.casters.size()) {
    if (j == d.casters.size() || (i < layer.casters.size() && layer.casters[i] < d.casters[j])) {
      mergedCasters_.push_back(layer.casters[i]);
      mergedLods_.push_back(layer.treeLods[i++]);
    } else {
      mergedCasters_.push_back(d.casters[j]);
      mergedLods_.push_back(lodOf(d.casters[j++]));
    }
  }
  std::swap(layer.casters, mergedCasters_);
  std::swap(layer.treeLods, mergedLods_);
  mergedBlocks_.clear();
  std::merge(layer.blocks.begin(), layer.blocks.end(), scratch_.begin(), scratch_.end(), std::back_inserter(mergedBlocks_), blockBefore);
  std::swap(layer.blocks, mergedBlocks_);
}

}  // namespace forest::render
