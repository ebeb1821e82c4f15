#include "bench_oracle.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <set>
#include <tuple>

#include "forest/core/frustum.hpp"
#include "forest/culling/reprojected_image.hpp"
#include "forest/gl/objects.hpp"
#include "forest/terrain/block_facing.hpp"
#include "forest/culling/occlusion_culler.hpp"

namespace forest::app {
namespace {

bool blockLess(const terrain::TileBlock& a, const terrain::TileBlock& b) {
  return std::tie(a.tile, a.level, a.block) < std::tie(b.tile, b.level, b.block);
}

}  // namespace

std::vector<VisibleSet> bruteForceVisibleSets(const render::SceneObjects& objects, const terrain::Terrain& terrain,
                                              const render::TerrainRenderer& terrainBlockIds, std::uint32_t blockIdBase,
                                              const render::TreeRenderer* treeIds, const render::PropRenderer* propIds,
                                              const culling::Bvh& bvh, const std::vector<Camera>& path, const SunSettings& sun,
                                              int width, int height, bool guessHidden, const std::function<void()>& progress) {
  gl::Texture idTexture(GL_R32UI, width, height), idDepth(GL_DEPTH_COMPONENT32F, width, height);
  gl::Framebuffer framebuffer;
  framebuffer.attach(GL_COLOR_ATTACHMENT0, idTexture);
  framebuffer.attach(GL_DEPTH_ATTACHMENT, idDepth);
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer.id());
  glViewport(0, 0, width, height);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_GREATER);  // reversed-Z
  glEnable(GL_CULL_FACE);
  glCullFace(GL_BACK);
  culling::OcclusionCuller culler;
  const std::uint32_t blocksPerTile = terrain::Terrain::kMaxBlockBoxes;
  const std::uint32_t blockIdEnd = blockIdBase + static_cast<std::uint32_t>(objects.tileCount()) * blocksPerTile;
  std::vector<std::uint32_t> pixels(static_cast<size_t>(width) * height);
  std::vector<float> depths(pixels.size());
  culling::SampledImage samples;  // the frame before's
  culling::ReprojectedImage reprojected;
  std::vector<VisibleSet> sets(path.size());
  for (size_t f = 0; f < path.size(); ++f) {
    const terrain::TerrainLod lod = terrain.lodFor(path[f], height);
    const GLuint none[4] = {0, 0, 0, 0};
    glClearBufferuiv(GL_COLOR, 0, none);
    const float farDepth = 0.0f;
    glClearBufferfv(GL_DEPTH, 0, &farDepth);
    render::SceneDrawer ids(objects, &terrainBlockIds, treeIds, propIds, path[f], &lod, 0.0, sun);
    const Frustum frustum(path[f]);
    ids.cullTerrainBlocks(&frustum);  // by blocks, so that each writes its own ID
    culler.cull(bvh, objects.boxes(), path[f], culling::CullingStrategy::None, ids);
    glGetTextureImage(idTexture.id(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, static_cast<GLsizei>(pixels.size() * 4), pixels.data());
    if (guessHidden)
      glGetTextureImage(idDepth.id(), 0, GL_DEPTH_COMPONENT, GL_FLOAT, static_cast<GLsizei>(depths.size() * 4), depths.data());
    std::set<std::uint32_t> seen;
    std::set<std::pair<int, int>> seenBlocks;
    for (std::uint32_t id : pixels) {
      if (id >= blockIdBase && id < blockIdEnd) {
        const std::uint32_t tile = (id - blockIdBase) / blocksPerTile;
        seen.insert(tile);  // tiles are the first objects
        seenBlocks.insert({static_cast<int>(tile), static_cast<int>((id - blockIdBase) % blocksPerTile)});
      } else if (const std::int64_t o = objects.objectOfId(id); o >= 0) {
        seen.insert(static_cast<std::uint32_t>(o));
      }
    }
    VisibleSet& set = sets[f];
    set.objects.assign(seen.begin(), seen.end());
    for (std::uint32_t o : set.objects) {
      if (objects.objects()[o].kind != render::SceneObjects::Kind::Tile) {
        set.notTerrain.push_back(o);
        continue;
      }
      const int level = terrain.tileLevel(static_cast<int>(o), lod);
      for (const Aabb& box : terrain.blockBoxes(static_cast<int>(o), level))
        if (frustum.mayIntersect(box)) set.wholeTileTriangles += 2LL * terrain::cellsPerBlock(level);
    }
    for (const auto& [tile, block] : seenBlocks) {
      set.blocks.push_back({tile, terrain.tileLevel(tile, lod), block});
      set.blockTriangles += 2LL * terrain::cellsPerBlock(set.blocks.back().level);
    }
    if (f > 0) {
      const VisibleSet& before = sets[f - 1];
      std::vector<std::uint32_t> gone, hiddenNow;
      std::set_difference(before.notTerrain.begin(), before.notTerrain.end(), set.notTerrain.begin(), set.notTerrain.end(),
                          std::back_inserter(gone));
      for (std::uint32_t o : gone)
        if (frustum.mayIntersect(objects.boxes()[o])) hiddenNow.push_back(o);
      std::vector<terrain::TileBlock> goneBlocks, hiddenBlocks;
      std::set_difference(before.blocks.begin(), before.blocks.end(), set.blocks.begin(), set.blocks.end(),
                          std::back_inserter(goneBlocks), blockLess);
      for (const terrain::TileBlock& b : goneBlocks)
        if (b.level == terrain.tileLevel(b.tile, lod) &&
            frustum.mayIntersect(terrain.blockBoxes(b.tile, b.level)[static_cast<size_t>(b.block)]))
          hiddenBlocks.push_back(b);
      // Into the ID target, already read.
      set.lagTriangles = ids.draw(hiddenNow) + (hiddenBlocks.empty() ? 0 : ids.drawTerrainBlocks(hiddenBlocks));
    }
    if (!guessHidden) {
      progress();
      continue;
    }
    if (f > 0) {  // the frame before's samples moved into this view
      const VisibleSet& before = sets[f - 1];
      std::vector<std::uint8_t> shown(objects.boxes().size(), 0);
      for (std::uint32_t o : before.notTerrain) shown[o] = 1;
      // One cell per sample where nothing moved, as the frame's ImageVisibility::hideByReprojection.
      reprojected.begin(path[f], static_cast<int>(samples.columns.size()), static_cast<int>(samples.rows.size()), shown, 0);
      reprojected.splat(samples);
      reprojected.clearHidden(shown);
      for (std::uint32_t o : before.notTerrain)
        if (shown[o] == 0) sets[f].hiddenByReprojection.push_back(o);
    }
    // This frame's samples: a pixel's eye depth from its depth (reversed-Z), and its object.
    const Camera& camera = path[f];
    samples.reset(camera, width, height);
    const int stride = culling::ReprojectedImage::kSampleStride;
    for (int y = 0, j = 0; y < height; y += stride, ++j) {
      for (int x = 0, i = 0; x < width; x += stride, ++i) {
        const std::size_t pixel = static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x);
        std::int64_t o = -1;
        if (pixels[pixel] >= blockIdBase && pixels[pixel] < blockIdEnd) o = (pixels[pixel] - blockIdBase) / blocksPerTile;
        else o = objects.objectOfId(pixels[pixel]);
        if (o < 0 || depths[pixel] <= 0.0f) continue;  // no sample
        const std::size_t sample = static_cast<std::size_t>(j) * samples.columns.size() + static_cast<std::size_t>(i);
        samples.depths[sample] = static_cast<float>(camera.eyeDepthOfReversedZ(depths[pixel]));
        samples.objects[sample] = static_cast<std::uint32_t>(o) + 1u;
      }
    }
    progress();
  }
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  return sets;
}

double wholeTileOracleTrianglesP50(const std::vector<VisibleSet>& sets, const std::vector<long long>& oracleTriangles, std::size_t from) {
  std::vector<double> whole;
  for (std::size_t f = from; f < sets.size() && f < oracleTriangles.size(); ++f)
    whole.push_back(static_cast<double>(oracleTriangles[f] - sets[f].blockTriangles + sets[f].wholeTileTriangles));
  if (whole.empty()) return 0.0;
  std::nth_element(whole.begin(), whole.begin() + static_cast<std::ptrdiff_t>(whole.size() / 2), whole.end());
  return whole[whole.size() / 2];
}

void recordShown(const VisibleSet& visible, std::size_t objects, std::size_t tiles, ShownRecord& out) {
  out.objects.assign(objects, 0);
  for (std::uint32_t o : visible.objects) out.objects[o] = 1;
  out.blocks.assign(tiles, 0);
  for (const terrain::TileBlock& b : visible.blocks)
    out.blocks[static_cast<std::size_t>(b.tile)] |= render::TerrainBlockVisibility::mapLevel(
        static_cast<std::uint16_t>(1u << b.block), b.level, 0, render::TerrainBlockVisibility::Combine::Any);
}

void clearHiddenByReprojection(const VisibleSet& now, ShownRecord& record) {
  for (std::uint32_t o : now.hiddenByReprojection) record.objects[o] = 0;
}

long long drawVisibleSet(render::SceneDrawer& drawer, const VisibleSet& visible) {
  return drawer.draw(visible.notTerrain) + (visible.blocks.empty() ? 0 : drawer.drawTerrainBlocks(visible.blocks));
}

double oracleLagShare(const std::vector<VisibleSet>& sets, const std::vector<long long>& oracleTriangles, std::size_t from) {
  double lag = 0.0, oracle = 0.0;
  for (std::size_t f = std::max<std::size_t>(1, from); f < sets.size() && f < oracleTriangles.size(); ++f) {
    lag += static_cast<double>(sets[f].lagTriangles);
    oracle += static_cast<double>(oracleTriangles[f]);
  }
  return lag / std::max(1.0, oracle);
}

DrawnBreakdown oracleTreesAndProps(const std::vector<VisibleSet>& sets, std::size_t from) {
  DrawnBreakdown sum;
  int frames = 0;
  std::vector<std::uint32_t> gone;
  for (std::size_t f = std::max<std::size_t>(1, from); f < sets.size(); ++f, ++frames) {
    gone.clear();
    std::set_difference(sets[f - 1].notTerrain.begin(), sets[f - 1].notTerrain.end(), sets[f].notTerrain.begin(),
                        sets[f].notTerrain.end(), std::back_inserter(gone));
    sum.visible += static_cast<double>(sets[f].notTerrain.size());
    sum.lag += static_cast<double>(gone.size());
  }
  const double n = std::max(1, frames);
  return {sum.visible / n, sum.lag / n, 0.0, 0.0};
}

void DrawnRecorder::beginFrame(render::SceneDrawer& drawer) {
  drawer_ = &drawer;
  drawn_.clear();
}

long long DrawnRecorder::draw(std::span<const std::uint32_t> objects) {
  for (std::uint32_t o : objects)
    if (objects_.objects()[o].kind != render::SceneObjects::Kind::Tile) drawn_.push_back(o);
  return drawer_->draw(objects);
}

void DrawnRecorder::endFrame(const VisibleSet& now, const VisibleSet* before, bool measured) {
  std::sort(drawn_.begin(), drawn_.end());
  drawn_.erase(std::unique(drawn_.begin(), drawn_.end()), drawn_.end());
  if (before && measured) {
    const auto in = [](const std::vector<std::uint32_t>& set, std::uint32_t o) { return std::binary_search(set.begin(), set.end(), o); };
    for (std::uint32_t o : drawn_) {
      if (in(now.notTerrain, o)) sum_.visible += 1.0;
      else if (in(before->notTerrain, o)) sum_.lag += 1.0;
      else if (in(drawnBefore_, o)) sum_.carried += 1.0;
      else sum_.fresh += 1.0;
    }
    ++frames_;
  }
  std::swap(drawn_, drawnBefore_);
  drawer_ = nullptr;
}

DrawnBreakdown DrawnRecorder::meanPerFrame() const {
  const double n = std::max(1, frames_);
  return {sum_.visible / n, sum_.lag / n, sum_.carried / n, sum_.fresh / n};
}

}  // namespace forest::app
