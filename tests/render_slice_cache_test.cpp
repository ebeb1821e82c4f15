// The slice cache's decisions (render/src/slice_cache.hpp) on the default scene's terrain and trees,
// each against what changed, computed here from the scene itself (a tree's LOD from
// vegetation::Forest::lodFor, the wind's reach from the transforms): a layer is reused while nothing
// it holds changed, added to for a caster it lacks, redrawn when a held caster's LOD, the matrices,
// the rectangle, a move or the wind beyond a texel changed. No GL: the cache only decides.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "../render/src/slice_cache.hpp"
#include "forest/core/scene.hpp"
#include "gl_test_support.hpp"
#include "test_paths.hpp"

namespace forest::render {
namespace {

using glm::dvec3;

struct CacheScene {
  Scene scene = loadScene(std::string(FOREST_REPO_DATA) + "/scenes/forest.toml");
  terrain::Terrain terrain{*scene.terrain};
  vegetation::Forest forest{*scene.vegetation, terrain};
  SceneObjects objects{&terrain, &forest, {}};

  // The object index of tree t.
  std::uint32_t treeObject(std::uint32_t t) const {
    for (std::uint32_t o = 0; o < objects.objects().size(); ++o)
      if (objects.objects()[o].kind == SceneObjects::Kind::Tree && objects.objects()[o].index == t) return o;
    throw Error("no tree " + std::to_string(t));
  }
};

// A map 200 m wide looking straight down over the scene's centre: texels of 200 / 1024 m.
ShadowSlice sliceOver(const Aabb& box) {
  ShadowSlice slice;
  glm::dmat4 m(0.0);
  const dvec3 c = box.centre();
  m[0][0] = 1.0 / 100.0;
  m[2][1] = 1.0 / 100.0;
  m[1][2] = -1.0 / 1000.0;
  m[3] = glm::dvec4(-c.x / 100.0, -c.z / 100.0, c.y / 1000.0, 1.0);
  slice.setup.worldToShadowClip = m;
  slice.setup.body = ConvexBody::fromBox(Aabb{c - dvec3(100.0, 50.0, 100.0), c + dvec3(100.0, 50.0, 100.0)});
  slice.setup.empty = false;
  return slice;
}

TEST(SliceCache, ReusesAddsAndRedrawsAsWhatItHoldsChanges) {
  CacheScene s;
  SliceCache cache(s.objects, nullptr, &s.forest);
  ShadowSlice slice = sliceOver(s.terrain.bounds());
  const LayerTarget target{1, 1024, 1024, 1, 0.0, true};
  const shadows::TexelRect read{100, 100, 900, 900};
  const dvec3 l(0.0, -1.0, 0.0);
  // Trees 0 and 1 cast; an eye and the first eye position along +x where tree 0's LOD changes
  // (what lodFor says, not the cache).
  slice.casters = {s.treeObject(0), s.treeObject(1)};
  const dvec3 base = s.forest.trees()[0].position;
  DrawView eye;
  eye.lodEye = base + dvec3(1.0, 2.0, 0.0);
  eye.time = 10.0;
  dvec3 lodChanged = eye.lodEye;
  while (s.forest.lodFor(0, lodChanged) == s.forest.lodFor(0, eye.lodEye)) lodChanged.x += 0.25;
  ASSERT_LT(lodChanged.x - eye.lodEye.x, 2000.0);
  auto planAndDraw = [&](const ShadowSlice& sl, const shadows::TexelRect& r, const DrawView& e) {
    const LayerDraw d = cache.plan(0, target, sl, r, e, nullptr, l);
    const std::string why(d.why);
    const SliceUpdate update = d.update;
    cache.drawn(0, target, d, sl, e, nullptr);
    return std::pair(update, why);
  };
  EXPECT_EQ(planAndDraw(slice, read, eye), std::pair(SliceUpdate::Redraw, std::string("first")));
  EXPECT_EQ(planAndDraw(slice, read, eye), std::pair(SliceUpdate::Reuse, std::string()));
  // A caster it lacks: added; then held.
  slice.casters.push_back(s.treeObject(2));
  EXPECT_EQ(planAndDraw(slice, read, eye).first, SliceUpdate::Add);
  EXPECT_EQ(planAndDraw(slice, read, eye).first, SliceUpdate::Reuse);
  // A caster no longer selected changes nothing.
  slice.casters.pop_back();
  EXPECT_EQ(planAndDraw(slice, read, eye).first, SliceUpdate::Reuse);
  // Lookups outside the rectangle drawn (the read one grown by kRectMarginShare per side).
  const int margin = static_cast<int>(std::ceil(kRectMarginShare * target.size));
  EXPECT_EQ(planAndDraw(slice, {100 - margin, 100, 900, 900}, eye).first, SliceUpdate::Reuse);
  EXPECT_EQ(planAndDraw(slice, {100 - margin - 1, 100, 900, 900}, eye), std::pair(SliceUpdate::Redraw, std::string("texels")));
  // Tree 0's LOD changes: redrawn; an eye that changes no held caster's LOD: reused.
  DrawView moved = eye;
  moved.lodEye = lodChanged;
  ASSERT_EQ(s.forest.lodFor(1, moved.lodEye), s.forest.lodFor(1, eye.lodEye)) << "pick an eye that moves one tree's LOD only";
  EXPECT_EQ(planAndDraw(slice, read, moved), std::pair(SliceUpdate::Redraw, std::string("lod")));
  EXPECT_EQ(planAndDraw(slice, read, moved).first, SliceUpdate::Reuse);
  // The wind: the tallest tree's top moves at most windShearChangeBound · height in dt; the
  // finest texel is 200 / 1024 m. A step it cannot cross a texel in is reused, one it can is not.
  const double texel = 200.0 / 1024.0, height = s.forest.tallestTree();
  const double rate = vegetation::windShearChangeBound(s.forest.settings(), 1e-3) / 1e-3 * height;  // m/s, dt small (linear part)
  ASSERT_GT(rate, 0.0);
  DrawView later = moved;
  later.time = moved.time + 0.5 * texel / rate;
  EXPECT_EQ(planAndDraw(slice, read, later).first, SliceUpdate::Reuse);
  later.time = moved.time + 1.5 * texel / rate;
  EXPECT_EQ(planAndDraw(slice, read, later), std::pair(SliceUpdate::Redraw, std::string("wind")));
  // Staggered (slice 2: staleFrames 3): the layer just redrawn for the wind keeps a held change for
  // three more frames and is redrawn on the fourth — every 2^2 frames at most.
  DrawView back = later;
  back.lodEye = eye.lodEye;  // tree 0 back to the LOD it had before
  for (int frame = 1; frame <= 3; ++frame) {
    const LayerDraw d = cache.plan(0, target, slice, read, back, nullptr, l, 3);
    EXPECT_EQ(d.update, SliceUpdate::Reuse) << "frame " << frame;
    EXPECT_EQ(d.deferred, "lod") << "frame " << frame;
    cache.drawn(0, target, d, slice, back, nullptr);
  }
  EXPECT_EQ(cache.plan(0, target, slice, read, back, nullptr, l, 3).why, "lod");
  // Other matrices, and objects that moved.
  slice.setup.worldToShadowClip[3][0] += 1e-9;
  EXPECT_EQ(planAndDraw(slice, read, later), std::pair(SliceUpdate::Redraw, std::string("matrices")));
  cache.forget();
  EXPECT_EQ(planAndDraw(slice, read, later).second, "first");
}

}  // namespace
}  // namespace forest::render
