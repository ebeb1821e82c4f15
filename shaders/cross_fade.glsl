// Inserted into the files that use it (gl::loadProgram "impostor.frag+cross_fade.glsl", trees.frag
// with CROSS_FADE).
// The cross-fade between a tree's mesh and its impostor over the switch band: at fade f the
// impostor keeps the pixels whose dither value is below f and the mesh the others, so where both
// cover a pixel exactly one writes it (interleaved gradient noise: Jimenez 2014).
float crossFadeDither(vec2 fragCoord) { return fract(52.9829189 * fract(dot(floor(fragCoord), vec2(0.06711056, 0.00583715)))); }
