#version 450 core
// Eye-space blur of the shadow term (thesis §6.3, §9.4.2) along one direction — linked into the
// blur passes (shadow_blur.frag) and, with the term at full resolution, into lighting, which then
// does the vertical pass itself.
// The radius shrinks with view depth so distant small shadows keep their detail:
//   r(z) = R · min(1, z_ref / z)   image pixels, z the eye depth of the centre pixel
// (R and z_ref: the frame block's blur.x and blur.y), a Gaussian with σ = r/2, cut at 3σ (weights
// below 1.1% of the centre's) and at R: distant pixels, where r shrinks below 0.67 px, read no
// neighbours at all. With the term at s = blur.w image pixels per texel (2: half resolution) the
// kernel is in texels, and the upsample's bilinear tent (half-width s image pixels, variance s²/6
// against full resolution's 1/6) already spreads the term: the blur keeps the image-space variance,
//   σ_s = sqrt(max(σ² − (s² − 1)/6, 0)) / s   texels,
// which at R = 3 near the eye is 0.66 texels, one tap each side.
// Depth-aware: a sample counts only when its eye depth is within blur.z (relative) of the
// centre's, so a shadow does not bleed across a silhouette. Texels: r = term, g = eye depth
// (0 = sky, kept as is; negated at half resolution where the surface faces away from the sun, so
// that the two sides of a terminator do not mix: shadow_term.frag).

// BLUR_TAPS: the most taps any pixel takes this frame (render/src/blur_pass.hpp: blurTapsBound), a
// compile-time loop bound, so the loop unrolls; a pixel that takes fewer weighs the rest 0.
const int kMaxTaps = 16;

vec2 blurTaps(sampler2D term, ivec2 pixel, ivec2 direction) {
  vec2 centre = texelFetch(term, pixel, 0).rg;
  float z = centre.g;
  if (z == 0.0) return centre;  // sky
  float scale = uFrame.blur.w, radius = uFrame.blur.x, tolerance = uFrame.blur.z;
  float sigmaImage = 0.5 * radius * min(1.0, uFrame.blur.y / abs(z));
  float sigma = max(sqrt(max(sigmaImage * sigmaImage - (scale * scale - 1.0) / 6.0, 0.0)) / scale, 0.25);
  int taps = min(min(kMaxTaps, int(ceil(radius / scale))), int(3.0 * sigma));
  ivec2 last = textureSize(term, 0) - 1;
  float sum = centre.r, weights = 1.0;
  // Gaussian weights w_i = q^(i²), q = e^(−1/(2σ²)), by recurrence: w_(i+1) = w_i · q^(2i+1).
  float q = exp(-0.5 / (sigma * sigma)), w = q, ratio = q * q * q;
  for (int i = 1; i <= BLUR_TAPS; ++i, w *= ratio, ratio *= q * q) {
    for (int side = -1; side <= 1; side += 2) {
      vec2 s = texelFetch(term, clamp(pixel + side * i * direction, ivec2(0), last), 0).rg;
      float same = (i <= taps && s.g != 0.0 && abs(s.g - z) <= tolerance * abs(z)) ? 1.0 : 0.0;
      sum += same * w * s.r;
      weights += same * w;
    }
  }
  return vec2(sum / weights, z);
}
