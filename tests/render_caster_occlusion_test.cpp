// The read-back path's choice whether culling the trees hidden from the sun pays
// (CasterOcclusion::worthCulling, HiddenCasters::Auto) prices a tree at what its draw submits: a
// tree beyond the impostor switch is one quad, not its mesh LOD. The rule's threshold — the two
// read-backs at 64 texels a triangle, the test free until measured — is set here between what the
// default forest's trees cost as meshes (their LODs from vegetation::Forest, summed here) and as
// impostors (2 triangles each), so the same layer pays with meshes and not with impostors. No GL.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "../render/src/caster_occlusion.hpp"
#include "forest/core/scene.hpp"
#include "test_paths.hpp"

namespace forest::render {
namespace {

TEST(CasterOcclusion, TreesBeyondTheImpostorSwitchArePricedAsTheirQuads) {
  const Scene scene = loadScene(std::string(FOREST_REPO_DATA) + "/scenes/forest.toml");
  const terrain::Terrain terrain{*scene.terrain};
  const vegetation::Forest forest{*scene.vegetation, terrain};
  const SceneObjects objects{&terrain, &forest, {}};
  WorkerThreads workers(1);
  std::vector<std::uint32_t> casters;
  for (std::uint32_t o = 0; o < objects.objects().size(); ++o)
    if (objects.objects()[o].kind == SceneObjects::Kind::Tree) casters.push_back(o);
  // An eye 2 km above the forest: every tree beyond a 600 m switch (its distance over its scale).
  const glm::dvec3 eye = terrain.bounds().centre() + glm::dvec3(0.0, 2000.0, 0.0);
  const ImpostorSwitch impostors{600.0, 0.1};
  long long meshTriangles = 0;
  for (std::uint32_t o : casters) {
    const std::uint32_t t = objects.objects()[o].index;
    ASSERT_GE(forest.lodDistance(t, eye), 600.0 * 1.1) << "tree " << t << " in or before the cross-fade band";
    meshTriangles += forest.model(forest.trees()[t].species).lods[static_cast<size_t>(forest.lodFor(t, eye))].triangleCount();
  }
  const long long quadTriangles = 2 * static_cast<long long>(casters.size());
  ASSERT_GT(meshTriangles, 2 * quadTriangles);
  // Read-backs worth the triangles halfway between: culling the untested trees (none counted yet,
  // all left out at the start) saves more than that as meshes, less as quads.
  const long long texels = 64 * (meshTriangles + quadTriangles) / 2;
  CasterOcclusion asMeshes(objects, workers), asImpostors(objects, workers);
  asMeshes.beginFrame();
  asImpostors.beginFrame();
  EXPECT_TRUE(asMeshes.worthCulling(casters, texels, eye, ImpostorSwitch{}));
  EXPECT_FALSE(asImpostors.worthCulling(casters, texels, eye, impostors));
}

}  // namespace
}  // namespace forest::render
