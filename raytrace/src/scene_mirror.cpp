#include "forest/raytrace/scene_mirror.hpp"

#include "forest/core/parallel.hpp"

namespace forest::raytrace {

void mirrorScene(RayScene& scene, const terrain::Terrain* terrain, const terrain::TerrainLod* lod,
                 const vegetation::Forest* forest, const Camera& camera, const MirrorOptions& options) {
  if (terrain && lod) {
    for (int tile = 0; tile < terrain->tileCount(); ++tile) {
      // Positions relative to the tile's box centre keep float precision far from the origin.
      const glm::dvec3 centre = terrain->tileBox(tile).centre();
      std::vector<glm::vec3> positions;
      std::vector<std::uint32_t> indices;
      for (const terrain::TerrainTriangle& t : terrain->drawnTriangles(tile, *lod)) {
        for (const glm::dvec3& v : t.vertices) {
          indices.push_back(static_cast<std::uint32_t>(positions.size()));
          positions.emplace_back(v - centre);
        }
      }
      const std::uint32_t mesh = scene.addMesh(positions, indices);
      glm::dmat4 toWorld(1.0);
      toWorld[3] = glm::dvec4(centre, 1.0);
      scene.addInstance(mesh, toWorld, options.terrainIdBase + static_cast<std::uint32_t>(tile));
    }
  }
  if (forest) {
    std::uint32_t meshes[vegetation::kSpeciesCount][vegetation::kTreeLods];
    for (int s = 0; s < vegetation::kSpeciesCount; ++s)
      for (int l = 0; l < vegetation::kTreeLods; ++l) {
        const vegetation::TreeMesh& m = forest->species()[s].lods[l];
        meshes[s][l] = scene.addMesh(m.positions, m.indices);
      }
    const auto addTree = [&](std::uint32_t t) {
      const int treeLod = forest->lodFor(t, camera.position);
      scene.addInstance(meshes[static_cast<int>(forest->trees()[t].species)][treeLod], forest->treeTransform(t, options.time),
                        options.treeIdBase + t);
    };
    if (options.trees)
      for (std::uint32_t t : *options.trees) addTree(t);
    else
      for (std::uint32_t t = 0; t < forest->trees().size(); ++t) addTree(t);
  }
  if (options.props && !options.props->empty()) {
    // A unit cube, outward-facing (counter-clockwise seen from outside), placed by scale + offset.
    const std::vector<glm::vec3> corners = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}, {1, 1, 1}};
    const std::vector<std::uint32_t> faces = {0, 2, 1, 1, 2, 3,  4, 5, 6, 5, 7, 6,  0, 1, 4, 1, 5, 4,
                                              2, 6, 3, 3, 6, 7,  0, 4, 2, 2, 4, 6,  1, 3, 5, 3, 7, 5};
    const std::uint32_t cube = scene.addMesh(corners, faces);
    for (std::uint32_t i = 0; i < options.props->size(); ++i) {
      const PropBox& box = (*options.props)[i];
      glm::dmat4 toWorld(1.0);
      for (int a = 0; a < 3; ++a) toWorld[a][a] = box.max[a] - box.min[a];
      toWorld[3] = glm::dvec4(box.min, 1.0);
      scene.addInstance(cube, toWorld, options.propIdBase + i);
    }
  }
  scene.commit();
}

std::vector<std::uint32_t> traceObjectIds(const RayScene& scene, const Camera& camera, int width, int height) {
  std::vector<std::uint32_t> ids(static_cast<size_t>(width) * height, kNoObject);
  const glm::dmat4 inverse = glm::inverse(camera.projection() * camera.view());
  const glm::dvec3 forward = camera.forward();
  parallelFor(height, [&](int y) {
      for (int x = 0; x < width; ++x) {
        const glm::dvec4 ndc(2.0 * (x + 0.5) / width - 1.0, 2.0 * (y + 0.5) / height - 1.0, 0.5, 1.0);
        const glm::dvec4 h = inverse * ndc;
        const glm::dvec3 direction = glm::normalize(glm::dvec3(h) / h.w - camera.position);
        // The near and far planes clip at eye depth, not at ray length.
        const double cosine = glm::dot(direction, forward);
        const RayHit hit = scene.intersect(camera.position, direction, camera.near / cosine, camera.far / cosine);
        if (hit.hit) ids[static_cast<size_t>(y) * width + x] = hit.objectId;
      }
  });
  return ids;
}

}  // namespace forest::raytrace
