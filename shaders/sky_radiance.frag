#version 450 core
// The sky's colour and the distance haze's (linear), linked into the sky pass (sky.frag) and the
// lighting (its haze).

// x^8 by squaring: pow is exp2(log2) on llvmpipe.
float pow8(float x) { x *= x; x *= x; return x * x; }

// The horizon's colour (linear): the zenith's, paled toward a hazy white.
vec3 horizonRadiance(vec3 zenith) { return mix(zenith, vec3(0.75, 0.8, 0.85), 0.55); }

// The sky (linear): the scene's sky colour at the zenith, paler toward the horizon (a gradient in
// elevation), a little darker below it, and, with the sun up, its disc (drawn 1.6° across so that
// it covers a few pixels; the real one is 0.53°) and a glow around it.
vec3 skyRadiance(vec3 d, vec3 zenith, vec3 toSun, vec3 sunColor, bool sunUp) {
  vec3 horizon = horizonRadiance(zenith);
  vec3 sky = d.y >= 0.0 ? mix(horizon, zenith, smoothstep(0.0, 0.6, d.y)) : horizon * (1.0 + 0.3 * d.y);
  if (!sunUp) return sky;
  float c = max(dot(d, toSun), 0.0);
  float disc = smoothstep(0.99985, 0.99990, c);  // cos 1.0° to cos 0.8°
  float c8 = pow8(c), c16 = c8 * c8, c128 = pow8(c16), c256 = c128 * c128;
  float glow = 0.6 * (c256 * c128 * c16) + 0.08 * c8;  // 0.6 c^400 + 0.08 c^8
  return sky + sunColor * (12.0 * disc + glow);
}

// The colour that distance haze fades toward along d: the horizon's, brighter toward the sun
// (light scattered forward).
vec3 hazeRadiance(vec3 d, vec3 zenith, vec3 toSun, vec3 sunColor, bool sunUp) {
  return horizonRadiance(zenith) + (sunUp ? 0.25 * sunColor * pow8(max(dot(d, toSun), 0.0)) : vec3(0.0));
}
