#pragma once
// The scene's objects as culling sees them: terrain tiles, then trees, then props, each with its
// box; and the drawer that renders any subset of them for one pass (culling::ObjectDrawer).
// Each tree is an object of its own, so visibility and shadow casters are decided per tree, not
// per cluster of trees (the BVH over the objects groups them; CHC++'s multiqueries and render
// queue keep the queries and draw calls few). Object IDs in the ID buffer: 0 is the sky; tiles,
// trees and props follow in blocks, so a pixel's object is known from its ID.
#include <cstdint>
#include <span>
#include <vector>

#include "forest/core/bounds.hpp"
#include "forest/core/camera.hpp"
#include "forest/core/frustum.hpp"
#include "forest/core/scene.hpp"
#include "forest/culling/occlusion_culler.hpp"
#include "forest/render/prop_renderer.hpp"
#include "forest/render/terrain_block_visibility.hpp"
#include "forest/render/terrain_renderer.hpp"
#include "forest/render/tree_renderer.hpp"

namespace forest::render {

class SceneObjects {
 public:
  SceneObjects(const terrain::Terrain* terrain, const vegetation::Forest* forest, const std::vector<PropBox>& props);

  enum class Kind { Tile, Tree, Prop };
  struct Object {
    Kind kind;
    std::uint32_t index;  // tile, tree or prop index
  };
  const std::vector<Aabb>& boxes() const { return boxes_; }
  // What occlusion queries draw for each object: a tree's height slabs
  // (vegetation::Forest::treeQueryBoxes), a terrain tile's blocks at the level `lod` draws it
  // (terrain::Terrain::blockBoxes; without a LOD, its box), a prop's box. Valid until the next call.
  culling::QueryShapes queryShapes(const terrain::TerrainLod* lod) const;
  const std::vector<Object>& objects() const { return objects_; }
  std::size_t queryBoxCount() const { return queryBoxes_.size(); }  // every object's query shapes
  // The boxes whose union holds a tree or a prop at all times (a tree's height slabs, a prop's
  // box): what its queries draw. Not for a tile, whose blocks depend on the LOD (queryShapes).
  std::span<const Aabb> shapeBoxes(std::uint32_t object) const;
  std::size_t tileCount() const { return tiles_; }
  const terrain::Terrain* terrain() const { return terrain_; }  // null without terrain
  const vegetation::Forest* forest() const { return forest_; }   // null without trees
  std::size_t treeCount() const { return trees_; }
  std::size_t propCount() const { return objects_.size() - tiles_ - trees_; }
  // Boxes again after trees or props moved.
  void updateBoxes(const vegetation::Forest* forest, const std::vector<PropBox>& props);
  // The same for the listed trees only (Frame::moveTrees: a frame moves a few of many trees).
  void updateTrees(const vegetation::Forest& forest, std::span<const vegetation::Forest::Move> moves);

  // The ID scheme of the geometry pass.
  std::uint32_t terrainIdBase() const { return 1; }
  std::uint32_t treeIdBase() const { return treeIdBase_; }
  std::uint32_t propIdBase() const { return propIdBase_; }
  // The culling object a pixel's ID belongs to; -1 for the sky.
  std::int64_t objectOfId(std::uint32_t id) const;

 private:
  // Object o's box and query shapes (written into the slots laid out at construction).
  void updateTree(const vegetation::Forest& forest, std::uint32_t tree);
  void updateProp(const PropBox& prop, std::uint32_t index);

  std::vector<Aabb> boxes_;
  std::vector<Object> objects_;
  const terrain::Terrain* terrain_ = nullptr;
  const vegetation::Forest* forest_ = nullptr;
  // Query shapes, laid out at construction: each tile owns kMaxBlockBoxes slots from the start,
  // rewritten for the LOD of each queryShapes call (hence mutable); then each tree's non-empty
  // slabs (how many depends on the species only) and each prop's box.
  mutable std::vector<culling::QueryShapes::Range> queryRanges_;
  mutable std::vector<Aabb> queryBoxes_;
  std::uint32_t tiles_ = 0, trees_ = 0;
  std::uint32_t treeIdBase_ = 1, propIdBase_ = 1;
};

// Draws subsets of the scene's objects with the given renderers (any may be null) for one view
// and terrain LOD.
class SceneDrawer : public culling::ObjectDrawer {
 public:
  SceneDrawer(const SceneObjects& objects, const TerrainRenderer* terrain, const TreeRenderer* trees,
              const PropRenderer* props, const DrawView& view, const terrain::TerrainLod* lod);
  // The eye's own view of the scene.
  SceneDrawer(const SceneObjects& objects, const TerrainRenderer* terrain, const TreeRenderer* trees,
              const PropRenderer* props, const Camera& camera, const terrain::TerrainLod* lod, double time,
              const SunSettings& sun)
      : SceneDrawer(objects, terrain, trees, props, DrawView::fromCamera(camera, time, sun), lod) {}
  long long draw(std::span<const std::uint32_t> objects) override;
  // Trees (TreeRenderer::drawQueries: with HullOrOwn the species' query hull where it has one)
  // and, with a LOD, terrain tiles (TerrainRenderer::drawQueries: the tile's triangles at its
  // level, all of them: those draw() leaves out are outside the frustum) can be queried with their
  // own triangles; props are queried with boxes. Exact near the eye: trees only — a tile whose box
  // meets the near plane is the ground under the walker, in view, and its query would draw its
  // finest level.
  bool queriesOwnGeometry(std::uint32_t object, culling::QueryGeometry geometry) const override;
  long long drawGeometryQueries(std::span<const std::uint32_t> objects, std::span<const std::uint32_t> slots,
                                culling::QueryGeometry geometry) override;
  // Draws from another view from now on (a pass keeps its drawer, and so its lists, from frame to
  // frame: no allocation per frame).
  void setView(const DrawView& view, const terrain::TerrainLod* lod) {
    view_ = view;
    lod_ = lod;
  }
  // With a frustum (the eye's, kept by the caller), a terrain tile is drawn by its blocks at its
  // level (terrain::Terrain::blockBoxes) whose boxes meet the frustum: a block outside it gives no
  // fragment, so the image is the same. Null: tiles whole (the default).
  // With `visibility` too, a tile's blocks it holds back are left to TerrainBlockVisibility (the
  // eye's occlusion culling by block: queried after the traversal, drawn by its drawLate).
  void cullTerrainBlocks(const Frustum* frustum, TerrainBlockVisibility* visibility = nullptr) {
    blockFrustum_ = frustum;
    blockVisibility_ = visibility;
  }
  // Blocks of tiles, each at its tile's level (TerrainRenderer::drawBlocks); returns the triangles.
  long long drawTerrainBlocks(std::span<const terrain::TileBlock> blocks);
  // Occlusion queries with the blocks' own triangles, block i into slot slots[i]
  // (TerrainRenderer::drawBlockQueries); returns the triangles.
  long long drawTerrainBlockQueries(std::span<const terrain::TileBlock> blocks, std::span<const std::uint32_t> slots);

 private:
  const SceneObjects& objects_;
  const TerrainRenderer* terrain_;
  const TreeRenderer* trees_;
  const PropRenderer* props_;
  DrawView view_;
  const terrain::TerrainLod* lod_;
  const Frustum* blockFrustum_ = nullptr;
  TerrainBlockVisibility* blockVisibility_ = nullptr;
  std::vector<int> tiles_;
  std::vector<terrain::TileBlock> blocks_;
  std::vector<std::uint32_t> treeList_, propList_, querySlots_, tileSlots_;
};

}  // namespace forest::render
