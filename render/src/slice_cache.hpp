#pragma once
// Cached slices (DESIGN §12, issue "Shadows that hold still", item 3): a layer of the shadow map
// that still holds what this frame's slice needs is not cleared and not redrawn. Kept slices
// (shadows/kept_slices.hpp) make a slice's matrices stay the same over many frames; what the layer
// holds then changes only where its casters do.
//
// A layer holds, per texel, the least depth over what was drawn into it — the same whatever the
// order of the draws. So a layer drawn at frame d serves frame f, after the casters selected at f
// that it lacks are drawn into it without a clear (an addition, at f's LODs), when
//   - its map, matrices (double, bit for bit), depth kind and draw state (bias, backside) are the
//     same, and the texels f's lookups read lie inside the rectangle drawn;
//   - every caster selected at f that it holds is as it was drawn: a tree at the same LOD, a
//     terrain block at the same level and cells, unmorphed or fully morphed both then and now, or
//     in a morph ramp drawn for the same eye position (CDLOD morphing moves vertices with the
//     eye's distance; a camera turning in place moves none); no object moved since
//     (Frame::moveTrees, props);
//   - the wind moved no point of a tree by as much as a texel since d: (f − d) seconds · the shear's
//     change bound · the tallest tree ≤ the layer's finest texel side across the light over f's
//     focus body (vegetation::windShearChangeBound, shadows::finestTexelSide). With the wind
//     still, a layer serves until something else changes.
// Staggered (issue item 3, "far slices may refresh on a staggered schedule"): a layer may also keep
// held casters that changed (a LOD, a morph, the wind) for up to `staleFrames` frames after its
// clear — the caller gives slice k 2^k − 1 — so far slices redraw at most every 2^k frames for
// them; what that costs is measured against the truth (forest bench speed-error).
// Held casters that are not selected at f change nothing anyone reads (they shadow no visible
// receiver). Otherwise the layer is cleared and f's casters drawn, into f's rectangle grown by
// kRectMarginShare of the map per side (lookups move as the camera does). Redrawing what it held
// too (so that receivers coming back into view find their casters) was measured and dropped: on
// the main walk the wind forces most redraws, and the union only added triangles
// (docs/experiments.md). The GPU's caster filter decides on the GPU what it draws: its layers are
// never cached.
#include <array>
#include <span>
#include <string_view>
#include <vector>

#include "forest/render/draw_view.hpp"
#include "forest/render/frame.hpp"
#include "forest/render/scene_objects.hpp"
#include "forest/terrain/terrain.hpp"
#include "forest/vegetation/forest.hpp"
#include "shadow_setup_pass.hpp"

namespace forest::render {

// A redrawn layer's rectangle: this frame's lookups' grown by this share of the map per side.
inline constexpr double kRectMarginShare = 0.02;

// The map a layer belongs to and how its casters are drawn into it.
struct LayerTarget {
  unsigned map = 0;  // the array texture's GL name
  int side = 0;      // its texels per side (a name may come back for a new texture)
  int size = 0;      // the layer's: the square at its origin (FrameSettings::farSliceScale)
  int layers = 0;
  double slopeScaleBias = 0.0;
  bool backside = true;
};

// What the shadow pass does with a layer this frame (SliceCache::plan).
struct LayerDraw {
  SliceUpdate update = SliceUpdate::Redraw;  // Reuse: nothing drawn; Add: no clear
  std::string_view why;                          // "" for Reuse; else SliceCache::plan's reason
  std::string_view deferred;                     // a held caster's change let stand (staggered), or ""
  std::span<const std::uint32_t> casters;        // the objects to draw (Add: only those it lacks)
  std::span<const terrain::TileBlock> blocks;    // the terrain blocks to draw (ShadowSlice::terrainByBlock)
  shadows::TexelRect rect;                       // the texels to draw into (a Redraw clears the layer first)
};

class SliceCache {
 public:
  SliceCache(const SceneObjects& objects, const terrain::Terrain* terrain, const vegetation::Forest* forest);

  // What to do with `layer` for `slice` this frame (valid until the next call). `read`: the texels
  // this frame's lookups read. Why not Reuse: "first" (nothing held: a first frame, or forgotten),
  // "map", "matrices", "lod", "terrain",
  // "wind", "texels" (a Redraw); "casters" (Add). `staleFrames`: how many frames after its clear a
  // layer may keep held casters that changed (0: none, exact).
  LayerDraw plan(int layer, const LayerTarget& target, const ShadowSlice& slice, const shadows::TexelRect& read, const DrawView& eye,
                 const terrain::TerrainLod* lod, const glm::dvec3& l, int staleFrames = 0);
  // `layer` now holds what `drawn` (plan's, carried out) drew for `eye`.
  void drawn(int layer, const LayerTarget& target, const LayerDraw& drawn, const ShadowSlice& slice, const DrawView& eye,
             const terrain::TerrainLod* lod);
  // Nothing drawn holds any more: objects moved, or a layer was drawn another way.
  void forget();
  void forget(int layer);

 private:
  struct DrawnBlock {
    terrain::TileBlock block;
    terrain::BlockMorph morph = terrain::BlockMorph::Morphing;
    glm::dvec3 eye{0.0};  // the LOD's eye it was drawn for: a morph follows the eye's distance
  };
  // The order the held and drawn blocks are kept in (sorted, merged, differenced).
  static bool blockBefore(const DrawnBlock& a, const DrawnBlock& b);
  struct Layer {
    bool valid = false;
    LayerTarget target;
    shadows::TexelRect rect;              // the texels drawn into
    glm::dmat4 worldToShadowClip{1.0};    // its matrices
    glm::dvec4 worldToLightDepth{0.0};
    bool linearDepth = false;
    std::vector<std::uint32_t> casters;   // increasing
    std::vector<std::uint8_t> treeLods;   // per caster: the LOD a tree was drawn at
    std::vector<DrawnBlock> blocks;       // increasing (tile, level, block, cells)
    bool terrainByBlock = false;
    terrain::TerrainLod lod;              // the terrain LOD's ramps (and eye) at the last clear
    double time = 0.0;                    // of the last clear: every caster was drawn since
    int age = 0;                          // frames since the last clear
  };
  static bool sameMatrices(const Layer& layer, const ShadowSlice& slice);
  // This frame's casters (increasing, into casters_) and terrain blocks (increasing, into blocks_).
  void current(const ShadowSlice& slice, const terrain::TerrainLod* lod);
  // The terrain casters' blocks as drawn now, increasing: `blocks` when drawn by block, else every
  // block of each tile among `casters` at its level.
  void blocksOf(bool byBlock, std::span<const terrain::TileBlock> blocks, std::span<const std::uint32_t> casters,
                const terrain::TerrainLod* lod, std::vector<DrawnBlock>& out) const;
  // "" when every current caster the layer holds is as it was drawn: its LOD, its terrain block's
  // level and morph, its sway within a texel; else what changed.
  // (casters_ and blocks_ hold this frame's.)
  std::string_view whyHeldChanged(const Layer& layer, const ShadowSlice& slice, const DrawView& eye, const glm::dvec3& l) const;
  // A clear and this frame's casters, into `read` grown by kRectMarginShare per side.
  LayerDraw redraw(std::string_view why, const shadows::TexelRect& read, int size);

  const SceneObjects& objects_;
  const terrain::Terrain* terrain_;
  const vegetation::Forest* forest_;
  double tallestTree_ = 0.0;
  std::array<Layer, shadows::kMaxCascades> layers_{};
  std::vector<std::uint32_t> casters_;  // this frame's, increasing
  std::vector<DrawnBlock> blocks_;      // this frame's terrain blocks, increasing
  std::vector<std::uint32_t> toDraw_;   // plan's casters
  std::vector<terrain::TileBlock> blocksToDraw_;
  std::vector<DrawnBlock> scratch_;
  std::vector<std::uint32_t> mergedCasters_;  // an addition's merge
  std::vector<std::uint8_t> mergedLods_;
  std::vector<DrawnBlock> mergedBlocks_;
};

}  // namespace forest::render
