#pragma once
// Procedural tree species (DESIGN §4 vegetation/): each tree is a union of closed, 2-manifold,
// outward-oriented components — capped tubes for trunk and branches, closed cones and lumpy blobs
// for crowns — built with OpenMesh; components may intersect (no CSG). The shadow pass renders
// back faces (thesis §5.1, §9.3), so every component must be closed. A LOD chain comes from
// quadric simplification (OpenMesh Decimater), each LOD still closed.
#include <glm/glm.hpp>

#include <array>
#include <cstdint>
#include <string_view>
#include <vector>

#include "forest/core/bounds.hpp"

namespace forest::vegetation {

enum class Species { Conifer, Broadleaf, Shrub };
constexpr int kSpeciesCount = 3;
constexpr Species kAllSpecies[kSpeciesCount] = {Species::Conifer, Species::Broadleaf, Species::Shrub};
constexpr int kTreeLods = 4;
std::string_view speciesName(Species species);

// One LOD of a species in object space: base at the origin, up +y, metres.
struct TreeMesh {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;
  std::vector<glm::vec3> albedo;            // linear RGB per vertex (bark, needles, leaves)
  std::vector<std::uint32_t> indices;       // triangles, counter-clockwise seen from outside
  std::vector<std::uint32_t> faceComponent; // closed component each triangle belongs to
  int components = 0;
  Aabb bounds;

  int triangleCount() const { return static_cast<int>(indices.size() / 3); }
};

struct SpeciesModel {
  Species species = Species::Conifer;
  std::array<TreeMesh, kTreeLods> lods;  // LOD i has about lod0Triangles / 4^i triangles
  std::array<int, kTreeLods> targetTriangles{};
  // A cheaper stand-in for the LODs in occlusion queries (culling's geometry queries), or empty:
  // closed convex pieces (faceComponent: the piece; counter-clockwise seen from outside) such that
  // each triangle of every LOD lies inside one piece. A piece's front faces then cover every pixel
  // the triangles inside it cover, nearer to the eye, under any affine transform of the tree (scale,
  // yaw, the wind's shear): a query with them that finds no sample proves the tree hidden. Only
  // where the shape is solid enough for its pieces to hug it (the thesis tree); a crown of leaves
  // would be wrapped with its gaps.
  TreeMesh queryHull;
};

// Triangle budget of LOD0: [1000, 20000]; LOD1 and LOD2 get a quarter and a sixteenth, at least
// 120 (11 closed components need ~4 triangles each, and a few more to keep their shape); LOD3, for
// trees a few tens of pixels high, a sixty-fourth, at least 48.
constexpr int kMinLod0Triangles = 1000;
constexpr int kMaxLod0Triangles = 20000;
std::array<int, kTreeLods> lodTriangleTargets(int lod0Triangles);

// Builds a species from its parameters and the seed (branch and blob layout). Throws
// InputError for a budget outside [kMinLod0Triangles, kMaxLod0Triangles].
SpeciesModel buildSpecies(Species species, int lod0Triangles, std::uint64_t seed);

// The thesis demo's tree (ch. 10; scene style "thesis"): a closed cone (32 slices × 2 stacks and a
// base cap: 32 + 64 + 32 = 128 triangles) and a closed torus ring (32 × 8 segments: 512 triangles),
// 640 triangles, 1 m high, the same at every LOD. The classic demo's 160-triangle cone counts 32
// zero-area triangles at the apex (GLU's quads), which a closed 2-manifold cannot contain.
constexpr int kThesisConeSlices = 32;
constexpr int kThesisTorusSegments = 32;
constexpr int kThesisTorusSides = 8;
constexpr int kThesisTreeTriangles = 640;
// Its query hull: a 16-sided pyramid around the cone and a 16-sided prism around the torus
// (circumscribed, grown by kThesisHullMargin): 30 + 60 = 90 triangles.
constexpr int kThesisHullSides = 16;
constexpr double kThesisHullMargin = 1e-3;  // metres of the 1 m tree: no face of the hull touches the tree
SpeciesModel buildThesisTree(Species species);

// Whether every triangle of `mesh` lies inside one closed convex piece of `hull`, each piece's
// faces pointing out (SpeciesModel::queryHull's contract; tests).
bool insideQueryHull(const TreeMesh& mesh, const TreeMesh& hull);

// Topology report of a mesh (tests): OpenMesh half-edge checks and the signed volume.
struct MeshTopology {
  int boundaryEdges = 0;       // edges with one face: 0 for closed
  int nonManifoldEdges = 0;    // edges shared by more than two faces, or with faces disagreeing on orientation
  double signedVolume = 0.0;   // > 0 for outward orientation
  std::vector<double> componentVolumes;
};
MeshTopology inspectMesh(const TreeMesh& mesh);

// True when two triangles of one component that share no vertex cross each other (an edge of one
// passes through the other): a fold or self-intersection. O(n²) with box pruning.
bool componentIntersectsItself(const TreeMesh& mesh, int component);

}  // namespace forest::vegetation
