// A tree's crown slab (vegetation/crown_slabs.hpp: PlacedCrownSlab) as a draw places it, and where
// a line crosses it; inserted into the shaders that test or clip against crown slabs
// (caster_filter.comp, impostor.frag). Heights [h.x, h.y] over the base (relative to the view's
// origin), the frustum's radius r.x at h.x and r.y at h.y (scaled), sheared by `shear` — in the
// unsheared frame (x − shear.x·y, z − shear.y·y) an upright frustum about the axis, wrapped in the
// octagonal one whose faces touch its circles (apothem = radius).
struct Crown {
  vec3 base;
  vec2 shear, h, r;
};

// The parameters [s0, s1] of the line a + s·d inside the slab's octagonal frustum with its faces
// moved out by `grow` — s0 > s1 where the line misses it: the line clipped by the ten planes
// (Cyrus–Beck) in the unsheared frame, where the line is mapped linearly (the same s).
vec2 crownSlabSpan(Crown c, float grow, vec3 a, vec3 d) {
  vec3 p = a - c.base;
  vec3 la = vec3(p.x - c.shear.x * p.y, p.y, p.z - c.shear.y * p.y);
  vec3 ld = vec3(d.x - c.shear.x * d.y, d.y, d.z - c.shear.y * d.y);
  float sNear = -1e30, sFar = 1e30;
  // Each plane as n·q ≤ k: the slab's floor and roof, then the eight sides, whose bound is the
  // radius at the point's height, ρ(y) = r.x + slope (y − h.x), grown.
  float slope = c.h.y > c.h.x ? (c.r.y - c.r.x) / (c.h.y - c.h.x) : 0.0;
  const float kHalfRoot2 = 0.70710678;  // (cos, sin) of k·π/4
  const vec2 kSides[8] = vec2[8](vec2(1.0, 0.0), vec2(kHalfRoot2, kHalfRoot2), vec2(0.0, 1.0), vec2(-kHalfRoot2, kHalfRoot2),
                                 vec2(-1.0, 0.0), vec2(-kHalfRoot2, -kHalfRoot2), vec2(0.0, -1.0), vec2(kHalfRoot2, -kHalfRoot2));
  float sideK = c.r.x - slope * c.h.x + grow * (1.0 + abs(slope));
  for (int i = 0; i < 10; ++i) {
    vec3 n;
    float k;
    if (i == 0) {
      n = vec3(0.0, -1.0, 0.0);
      k = -(c.h.x - grow);
    } else if (i == 1) {
      n = vec3(0.0, 1.0, 0.0);
      k = c.h.y + grow;
    } else {
      n = vec3(kSides[i - 2].x, -slope, kSides[i - 2].y);
      k = sideK;
    }
    float along = dot(n, ld), at = k - dot(n, la);  // inside: at − s·along ≥ 0
    if (abs(along) < 1e-20) {
      if (at < 0.0) return vec2(1.0, 0.0);
      continue;
    }
    float s = at / along;
    if (along > 0.0) sFar = min(sFar, s);
    else sNear = max(sNear, s);
  }
  return vec2(sNear, sFar);
}
