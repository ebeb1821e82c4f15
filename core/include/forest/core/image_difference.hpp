#pragma once
// How far apart two images of one view are: per-pixel differences (what a change of a pass may
// move) and the structural similarity index of Wang, Bovik, Sheikh & Simoncelli, "Image Quality
// Assessment: From Error Visibility to Structural Similarity" (IEEE TIP 13(4), 2004) — the
// perceptual measure the impostors' error is stated in (issue "Far trees as impostors").
#include <cstdint>
#include <vector>

#include "forest/core/image.hpp"

namespace forest {

struct PixelDifference {
  double meanAbsolute = 0.0;  // mean |Δ| over the colour channels, in 1/255
  double shareOver8 = 0.0;    // share of pixels where some colour channel differs by more than 8/255
};
// Throws InputError unless both images have the same size and 3 or 4 channels.
PixelDifference pixelDifference(const Image8& a, const Image8& b);
// Over the pixels where mask is non-zero (one byte a pixel, the images' order): the shares are of
// those pixels (0 where there are none). Throws InputError unless the mask has a byte per pixel.
PixelDifference pixelDifference(const Image8& a, const Image8& b, const std::vector<std::uint8_t>& mask);

// Mean SSIM (the paper's eq. 13, MSSIM) of the images' luma Y = 0.2126 R + 0.7152 G + 0.0722 B
// (one channel: the channel itself), with its recommended parameters: an 11 × 11 circular-symmetric
// Gaussian window of σ = 1.5 samples normalised to unit sum, weighted statistics (eq. 14–16),
// C1 = (0.01 · 255)², C2 = (0.03 · 255)² (eq. 7, 10), over every window that lies inside the image:
//   SSIM = (2 μx μy + C1)(2 σxy + C2) / ((μx² + μy² + C1)(σx² + σy² + C2))        (eq. 13)
// 1 for identical images; lower for less alike. Throws InputError unless the images have the same
// size, 1, 3 or 4 channels, and at least 11 × 11 pixels.
double meanSsim(const Image8& a, const Image8& b);
// The mean over the windows whose centre pixel is in the mask (1 where there are none).
double meanSsim(const Image8& a, const Image8& b, const std::vector<std::uint8_t>& mask);

}  // namespace forest
