#include "forest/render/scene_objects.hpp"

namespace forest::render {

SceneObjects::SceneObjects(const terrain::Terrain* terrain, const vegetation::Forest* forest,
                           const std::vector<PropBox>& props) {
  if (terrain) {
    tiles_ = static_cast<std::uint32_t>(terrain->tileCount());
    for (std::uint32_t t = 0; t < tiles_; ++t) objects_.push_back({Kind::Tile, t});
  }
  if (forest) {
    clusters_ = static_cast<std::uint32_t>(forest->clusters().size());
    for (std::uint32_t c = 0; c < clusters_; ++c) objects_.push_back({Kind::Cluster, c});
    clusterOfTree_.assign(forest->trees().size(), 0);
    for (std::uint32_t c = 0; c < clusters_; ++c)
      for (std::uint32_t t : forest->clusters()[c].trees) clusterOfTree_[t] = c;
  }
  for (std::uint32_t p = 0; p < props.size(); ++p) objects_.push_back({Kind::Prop, p});
  treeIdBase_ = 1 + tiles_;
  propIdBase_ = treeIdBase_ + static_cast<std::uint32_t>(clusterOfTree_.size());
  boxes_.resize(objects_.size());
  if (terrain)
    for (std::uint32_t t = 0; t < tiles_; ++t) boxes_[t] = terrain->tileBox(static_cast<int>(t));
  updateBoxes(forest, props);
}

void SceneObjects::updateBoxes(const vegetation::Forest* forest, const std::vector<PropBox>& props) {
  for (std::uint32_t c = 0; c < clusters_; ++c) boxes_[tiles_ + c] = forest->clusters()[c].bounds;
  for (std::uint32_t p = 0; p < props.size(); ++p) boxes_[tiles_ + clusters_ + p] = Aabb{props[p].min, props[p].max};
}

std::int64_t SceneObjects::objectOfId(std::uint32_t id) const {
  if (id == 0) return -1;
  if (id < treeIdBase_) return id - 1;
  if (id < propIdBase_) return tiles_ + clusterOfTree_[id - treeIdBase_];
  return tiles_ + clusters_ + (id - propIdBase_);
}

SceneDrawer::SceneDrawer(const SceneObjects& objects, const TerrainRenderer* terrain, const TreeRenderer* trees,
                         const PropRenderer* props, const DrawView& view, const terrain::TerrainLod* lod)
    : objects_(objects), terrain_(terrain), trees_(trees), props_(props), view_(view), lod_(lod) {
  // Room for every object: a draw never grows the lists (no allocation per frame).
  tiles_.reserve(objects.tileCount());
  clusters_.reserve(objects.clusterCount());
  propList_.reserve(objects.propCount());
}

long long SceneDrawer::draw(std::span<const std::uint32_t> objects) {
  tiles_.clear();
  clusters_.clear();
  propList_.clear();
  for (std::uint32_t o : objects) {
    const SceneObjects::Object& object = objects_.objects()[o];
    switch (object.kind) {
      case SceneObjects::Kind::Tile: tiles_.push_back(static_cast<int>(object.index)); break;
      case SceneObjects::Kind::Cluster: clusters_.push_back(object.index); break;
      case SceneObjects::Kind::Prop: propList_.push_back(object.index); break;
    }
  }
  long long triangles = 0;
  if (terrain_ && lod_ && !tiles_.empty()) triangles += terrain_->draw(view_, *lod_, tiles_).triangles;
  if (trees_ && !clusters_.empty()) triangles += trees_->draw(view_, clusters_).triangles;
  if (props_ && !propList_.empty()) triangles += props_->draw(view_, propList_);
  return triangles;
}

}  // namespace forest::render
