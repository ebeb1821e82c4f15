#version 450 core
// Display encoding: linear radiance → display value, γ 2.2 (x^(1/2.2) on [0, 1]), linked into the
// lighting pass. Not pow: on llvmpipe pow is a log2 and an exp2 per channel, ~1.5 ms of the
// 800 × 600 lighting pass (thesis walk, 5184 trees); this costs three square roots. A least-squares
// fit of x^(1/2.2) over x^(1/2), x^(1/4), x^(1/8), x and x^(3/2) on a grid uniform in x and in
// log x (down to 1e-9), reweighted toward its largest error (minimax): |error| ≤ 0.12 / 255 on
// [0, 1] — under a quarter of an 8-bit step — exact at 0, 1.0004 at 1 (stored as 255). Test:
// gl_shader_test DisplayGammaIsWithinAQuarterStepOfPow.
vec3 displayFromLinear(vec3 linear) {
  vec3 x = clamp(linear, 0.0, 1.0);
  vec3 r2 = sqrt(x), r4 = sqrt(r2), r8 = sqrt(r4);
  return 1.0165150 * r2 + 0.0933966 * r4 - 0.0121831 * r8 - 0.1519660 * x + 0.0546789 * x * r2;
}
