#pragma once
// Far trees' impostors, baked (issue "Far trees as impostors that cast shadows"): every species'
// LOD0 rendered by the engine from each view of a hemi-octahedral grid (vegetation/impostor_views.hpp)
// into one layer of an RGBA32UI array texture — per texel the surface nearest the viewer (its
// distance from the bake plane, albedo with coverage, shading normal) and the nearest surface seen
// from behind (the far side a backside shadow map stores when the bake view is the light's).
// Size classes share their species' bake: they differ only in scale.
#include <glm/glm.hpp>

#include <array>
#include <vector>

#include "forest/gl/objects.hpp"
#include "forest/gl/shader.hpp"
#include "forest/render/uniform_blocks.hpp"
#include "forest/vegetation/forest.hpp"
#include "forest/vegetation/impostor_views.hpp"

namespace forest::render {

constexpr int kImpostorViews = 16;   // bake views per side of the hemi-octahedral grid
constexpr int kImpostorTexels = 48;  // texels per side of one view

// One atlas texel, unpacked (shaders/impostor_bake.frag packs it).
struct ImpostorTexel {
  bool covered = false;
  double front = 0.0, back = 0.0;  // distance from the bake plane to the nearest surface, and to the nearest one facing away
  glm::dvec3 albedo{0.0};          // linear RGB (before the tree's tint)
  glm::dvec3 normal{0.0};          // shading normal, object space (10 bits an axis)
};
ImpostorTexel unpackImpostorTexel(const glm::uvec4& packed);

class ImpostorAtlas {
 public:
  // Bakes every species with meshes; `views` × `views` views of `texels`² texels each.
  explicit ImpostorAtlas(const vegetation::Forest& forest, int views = kImpostorViews, int texels = kImpostorTexels);

  const gl::Texture& texture() const { return texture_; }  // RGBA32UI array, one layer per species
  // Binds the texture and the ImpostorBlock (the layout, the species' spheres, boxes and slabs)
  // where impostor.vert and impostor.frag read them.
  void bind() const;
  const vegetation::ImpostorGrid& grid() const { return grid_; }
  int texelsPerView() const { return texels_; }
  const vegetation::ImpostorSphere& sphere(vegetation::Species species) const { return spheres_[static_cast<size_t>(species)]; }
  double bakeSeconds() const { return bakeSeconds_; }
  // The largest error an impostor shows in object space (metres), over the species: a bake texel
  // (the sphere's diameter over a view's texels) or the parallax of a surface point up to R from
  // the bake plane's centre seen up to the grid's largest angle off its view, R sin θ — whichever is
  // larger; and the distance beyond which that covers at most a pixel of a frame `heightPixels`
  // high with a vertical field of view `fovy` (radians): a screen-space bound like the LOD bands',
  // in the distance over the size class's scale that the switch compares (a tree s times as large
  // errs s times as much, and switches s times as far).
  double largestError() const;
  double switchDistance(double fovy, int heightPixels) const;

  // The object-space point of view (i, j)'s bake plane at `texel` (texel units along right and up
  // from the view's lower left corner: (x + 0.5, y + 0.5) is texel (x, y)'s centre), gone `s`
  // along −toViewer.
  glm::dvec3 bakePoint(vegetation::Species species, int i, int j, const glm::dvec2& texel, double s) const;
  // Layer `species` read back from the GPU, row by row (width views × texels).
  std::vector<glm::uvec4> download(vegetation::Species species) const;

 private:
  void bakeSpecies(const vegetation::SpeciesModel& model, const gl::Program& program, std::vector<glm::uvec4>& layer) const;

  vegetation::ImpostorGrid grid_;
  int texels_;
  std::array<vegetation::ImpostorSphere, vegetation::kSpeciesCount> spheres_{};
  gl::Texture texture_;
  gl::Buffer block_;  // ImpostorBlock
  double bakeSeconds_ = 0.0;
};

}  // namespace forest::render
