// Far trees' impostors (render/impostor_atlas.hpp): the bake's layout and the species' volumes,
// prepended to impostor.vert and impostor.frag. ImpostorBlock (render/uniform_blocks.hpp, std140,
// binding 4), written once at the bake:
layout(std140, binding = 4) uniform ImpostorBlock {
  ivec4 grid;             // x: views a side, y: texels a view side
  vec4 sphere[4];         // per species: the bake sphere's centre (object space) and radius
  vec4 boxMin[4];         // per species: its box over all LODs (object space)
  vec4 boxMax[4];
  vec4 querySlabs[16];    // species s, slab k (4 a species): height range, radius (Forest::querySlabs)
  vec4 casterSlabs[32];   // species s, slab k (8 a species): height range, frustum radii (Forest::casterSlabs)
} uImpostor;
