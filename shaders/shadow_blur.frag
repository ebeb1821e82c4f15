#version 450 core
// Eye-space blur of the shadow term (thesis §6.3, §9.4.2), one direction per pass (separable).
// The radius shrinks with view depth so distant small shadows keep their detail:
//   r(z) = uRadius · min(1, uReferenceDepth / z)   pixels, z the eye depth of the centre pixel.
// Depth-aware: a sample counts only when its eye depth is within uDepthTolerance (relative) of the
// centre's, so a shadow does not bleed across a silhouette. Sky pixels keep the term 1.
in vec2 vUv;

uniform sampler2D uShadowTerm;
uniform sampler2D uDepth;          // reversed-Z
uniform usampler2D uObjectId;
uniform ivec2 uDirection;          // (1, 0) or (0, 1)
uniform float uRadius;             // pixels at depths up to uReferenceDepth; > 0
uniform float uReferenceDepth;     // metres
uniform float uDepthTolerance;     // relative eye-depth difference that still counts as the same surface
uniform float uNear;
uniform float uFar;

out float blurred;

const int kMaxTaps = 16;

float eyeDepth(float d) { return uNear * uFar / (uNear + d * (uFar - uNear)); }  // reversed-Z → metres

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  float centre = texelFetch(uShadowTerm, pixel, 0).r;
  if (texelFetch(uObjectId, pixel, 0).r == 0u) { blurred = centre; return; }
  float z = eyeDepth(texelFetch(uDepth, pixel, 0).r);
  float r = uRadius * min(1.0, uReferenceDepth / z);
  int taps = min(kMaxTaps, int(ceil(r)));
  if (taps == 0) { blurred = centre; return; }
  float sigma = max(r / 2.0, 0.5);
  ivec2 size = textureSize(uShadowTerm, 0);
  float sum = centre, weights = 1.0;
  for (int i = -taps; i <= taps; ++i) {
    if (i == 0) continue;
    ivec2 q = pixel + i * uDirection;
    if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size))) continue;
    if (texelFetch(uObjectId, q, 0).r == 0u) continue;
    float zq = eyeDepth(texelFetch(uDepth, q, 0).r);
    if (abs(zq - z) > uDepthTolerance * z) continue;
    float w = exp(-float(i * i) / (2.0 * sigma * sigma));
    sum += w * texelFetch(uShadowTerm, q, 0).r;
    weights += w;
  }
  blurred = sum / weights;
}
