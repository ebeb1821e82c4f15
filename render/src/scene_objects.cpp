#include "forest/render/scene_objects.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <string>

#include "forest/core/error.hpp"

namespace forest::render {

SceneObjects::SceneObjects(const terrain::Terrain* terrain, const vegetation::Forest* forest,
                           const std::vector<PropBox>& props) {
  terrain_ = terrain;
  forest_ = forest;
  if (terrain) {
    tiles_ = static_cast<std::uint32_t>(terrain->tileCount());
    for (std::uint32_t t = 0; t < tiles_; ++t) objects_.push_back({Kind::Tile, t});
  }
  if (forest) {
    trees_ = static_cast<std::uint32_t>(forest->trees().size());
    for (std::uint32_t t = 0; t < trees_; ++t) objects_.push_back({Kind::Tree, t});
  }
  for (std::uint32_t p = 0; p < props.size(); ++p) objects_.push_back({Kind::Prop, p});
  treeIdBase_ = 1 + tiles_;
  propIdBase_ = treeIdBase_ + trees_;
  boxes_.resize(objects_.size());
  if (terrain)
    for (std::uint32_t t = 0; t < tiles_; ++t) boxes_[t] = terrain->tileBox(static_cast<int>(t));
  queryRanges_.assign(objects_.size(), {});
  std::uint32_t slots = tiles_ * terrain::Terrain::kMaxBlockBoxes;
  for (std::uint32_t o = tiles_; o < objects_.size(); ++o) {
    std::uint32_t count = 1;
    if (objects_[o].kind == Kind::Tree) {
      const auto slabs = forest->treeQueryBoxes(objects_[o].index);
      count = static_cast<std::uint32_t>(std::count_if(slabs.begin(), slabs.end(), [](const Aabb& b) { return b.valid(); }));
    }
    queryRanges_[o] = {slots, count};
    slots += count;
  }
  queryBoxes_.resize(slots);
  updateBoxes(forest, props);
}

void SceneObjects::updateTree(const vegetation::Forest& forest, std::uint32_t tree) {
  const std::uint32_t o = tiles_ + tree;
  boxes_[o] = forest.treeBounds(tree);
  auto slot = queryBoxes_.begin() + queryRanges_[o].first;
  for (const Aabb& slab : forest.treeQueryBoxes(tree))
    if (slab.valid()) *slot++ = slab;
}

void SceneObjects::updateProp(const PropBox& prop, std::uint32_t index) {
  const std::uint32_t o = tiles_ + trees_ + index;
  boxes_[o] = Aabb{prop.min, prop.max};
  queryBoxes_[queryRanges_[o].first] = boxes_[o];
}

void SceneObjects::updateBoxes(const vegetation::Forest* forest, const std::vector<PropBox>& props) {
  for (std::uint32_t t = 0; t < trees_; ++t) updateTree(*forest, t);
  for (std::uint32_t p = 0; p < props.size(); ++p) updateProp(props[p], p);
}

void SceneObjects::updateTrees(const vegetation::Forest& forest, std::span<const vegetation::Forest::Move> moves) {
  for (const vegetation::Forest::Move& move : moves) updateTree(forest, move.tree);
}

culling::QueryShapes SceneObjects::queryShapes(const terrain::TerrainLod* lod) const {
  for (std::uint32_t t = 0; t < tiles_; ++t) {
    const std::uint32_t first = t * terrain::Terrain::kMaxBlockBoxes;
    if (!lod) {
      queryBoxes_[first] = boxes_[t];
      queryRanges_[t] = {first, 1};
      continue;
    }
    const std::span<const Aabb> blocks = terrain_->blockBoxes(static_cast<int>(t), terrain_->tileLevel(static_cast<int>(t), *lod));
    std::copy(blocks.begin(), blocks.end(), queryBoxes_.begin() + first);
    queryRanges_[t] = {first, static_cast<std::uint32_t>(blocks.size())};
  }
  return {queryRanges_, queryBoxes_};
}

std::span<const Aabb> SceneObjects::shapeBoxes(std::uint32_t object) const {
  if (object < tiles_ || object >= objects_.size()) throw Error("scene objects: no tree or prop " + std::to_string(object));
  const culling::QueryShapes::Range range = queryRanges_[object];
  return {queryBoxes_.data() + range.first, range.count};
}

std::int64_t SceneObjects::objectOfId(std::uint32_t id) const {
  if (id == 0 || id > objects_.size()) return -1;
  return id - 1;  // tiles, trees and props take consecutive IDs from 1 in object order
}

SceneDrawer::SceneDrawer(const SceneObjects& objects, const TerrainRenderer* terrain, const TreeRenderer* trees,
                         const PropRenderer* props, const DrawView& view, const terrain::TerrainLod* lod)
    : objects_(objects), terrain_(terrain), trees_(trees), props_(props), view_(view), lod_(lod) {
  // Room for every object: a draw never grows the lists (no allocation per frame).
  tiles_.reserve(objects.tileCount());
  blocks_.reserve(objects.tileCount() * terrain::Terrain::kMaxBlockBoxes);
  treeList_.reserve(objects.treeCount());
  querySlots_.reserve(objects.treeCount());
  tileSlots_.reserve(objects.tileCount());
  propList_.reserve(objects.propCount());
}

bool SceneDrawer::queriesOwnGeometry(std::uint32_t object, culling::QueryGeometry geometry) const {
  switch (objects_.objects()[object].kind) {
    case SceneObjects::Kind::Tree: return trees_ != nullptr;
    case SceneObjects::Kind::Tile: return terrain_ != nullptr && lod_ != nullptr && geometry == culling::QueryGeometry::HullOrOwn;
    case SceneObjects::Kind::Prop: break;
  }
  return false;
}

long long SceneDrawer::drawGeometryQueries(std::span<const std::uint32_t> objects, std::span<const std::uint32_t> slots,
                                           culling::QueryGeometry geometry) {
  treeList_.clear();
  querySlots_.clear();
  tiles_.clear();
  tileSlots_.clear();
  for (std::size_t i = 0; i < objects.size(); ++i) {
    if (!queriesOwnGeometry(objects[i], geometry)) throw Error(fmt::format("SceneDrawer: a geometry query for object {}, which has none", objects[i]));
    const SceneObjects::Object& object = objects_.objects()[objects[i]];
    if (object.kind == SceneObjects::Kind::Tile) {
      tiles_.push_back(static_cast<int>(object.index));
      tileSlots_.push_back(slots[i]);
    } else {
      treeList_.push_back(object.index);
      querySlots_.push_back(slots[i]);
    }
  }
  long long triangles = 0;
  if (!treeList_.empty())
    triangles += trees_->drawQueries(view_, treeList_, querySlots_, geometry == culling::QueryGeometry::HullOrOwn).triangles;
  if (!tiles_.empty()) triangles += terrain_->drawQueries(view_, *lod_, tiles_, tileSlots_).triangles;
  return triangles;
}

long long SceneDrawer::drawTerrainBlocks(std::span<const terrain::TileBlock> blocks) {
  if (!terrain_ || !lod_) throw Error("SceneDrawer::drawTerrainBlocks: no terrain renderer or LOD");
  return terrain_->drawBlocks(view_, *lod_, blocks).triangles;
}

long long SceneDrawer::drawTerrainBlockQueries(std::span<const terrain::TileBlock> blocks, std::span<const std::uint32_t> slots) {
  if (!terrain_ || !lod_) throw Error("SceneDrawer::drawTerrainBlockQueries: no terrain renderer or LOD");
  return terrain_->drawBlockQueries(view_, *lod_, blocks, slots).triangles;
}

long long SceneDrawer::draw(std::span<const std::uint32_t> objects) {
  tiles_.clear();
  treeList_.clear();
  propList_.clear();
  for (std::uint32_t o : objects) {
    const SceneObjects::Object& object = objects_.objects()[o];
    switch (object.kind) {
      case SceneObjects::Kind::Tile: tiles_.push_back(static_cast<int>(object.index)); break;
      case SceneObjects::Kind::Tree: treeList_.push_back(object.index); break;
      case SceneObjects::Kind::Prop: propList_.push_back(object.index); break;
    }
  }
  // Trees and props before the terrain: the terrain's fragments (the costlier material) behind them
  // then fail the depth test before shading. The depth test decides the image either way.
  long long triangles = 0;
  if (trees_ && !treeList_.empty()) triangles += trees_->draw(view_, treeList_).triangles;
  if (props_ && !propList_.empty()) triangles += props_->draw(view_, propList_);
  if (terrain_ && lod_ && !tiles_.empty()) {
    if (blockFrustum_ && objects_.terrain()) {
      const terrain::Terrain& terrain = *objects_.terrain();
      blocks_.clear();
      for (int tile : tiles_) {
        const int level = terrain.tileLevel(tile, *lod_);
        const std::span<const Aabb> boxes = terrain.blockBoxes(tile, level);
        for (int b = 0; b < static_cast<int>(boxes.size()); ++b)
          if (blockFrustum_->mayIntersect(boxes[static_cast<size_t>(b)]) && (!blockVisibility_ || blockVisibility_->drawNow(tile, level, b)))
            blocks_.push_back({tile, level, b});
      }
      if (!blocks_.empty()) triangles += terrain_->drawBlocks(view_, *lod_, blocks_).triangles;
    } else {
      triangles += terrain_->draw(view_, *lod_, tiles_).triangles;
    }
  }
  return triangles;
}

}  // namespace forest::render
