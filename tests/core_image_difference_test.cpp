// Image differences (core/image_difference.hpp): per-pixel differences on pairs whose answer is a
// closed form, and SSIM (Wang et al. 2004) against its closed form on constant images and a brute
// force of the paper's definitions (every window summed directly in 2D, the statistics in two
// passes) on random ones.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "forest/core/error.hpp"
#include "forest/core/image_difference.hpp"

namespace forest {
namespace {

Image8 randomImage(int width, int height, int channels, unsigned seed) {
  Image8 image(width, height, channels);
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> value(0, 255);
  for (std::uint8_t& v : image.pixels) v = static_cast<std::uint8_t>(value(rng));
  return image;
}

Image8 grey(int width, int height, int value) {
  Image8 image(width, height, 3);
  for (std::uint8_t& v : image.pixels) v = static_cast<std::uint8_t>(value);
  return image;
}

// The paper's MSSIM on one-channel images by its definitions: an 11 × 11 window of weights
// exp(−(i² + j²) / (2 · 1.5²)) normalised to unit sum (§III-C), eq. 14–16 computed as weighted
// sums of deviations, eq. 13 with C1 = (0.01 · 255)², C2 = (0.03 · 255)², averaged over the windows
// inside the image.
// With a mask: the windows whose centre pixel (x0 + 5, y0 + 5) is in it.
double bruteForceSsim(const Image8& a, const Image8& b, const std::vector<std::uint8_t>* mask = nullptr) {
  double w[11][11], total = 0.0;
  for (int j = 0; j < 11; ++j)
    for (int i = 0; i < 11; ++i) total += w[j][i] = std::exp(-((i - 5) * (i - 5) + (j - 5) * (j - 5)) / (2.0 * 1.5 * 1.5));
  const double c1 = std::pow(0.01 * 255.0, 2.0), c2 = std::pow(0.03 * 255.0, 2.0);
  double sum = 0.0;
  int windows = 0;
  for (int y0 = 0; y0 + 11 <= a.height; ++y0)
    for (int x0 = 0; x0 + 11 <= a.width; ++x0) {
      if (mask && !(*mask)[static_cast<size_t>((y0 + 5) * a.width + x0 + 5)]) continue;
      double mx = 0.0, my = 0.0;
      for (int j = 0; j < 11; ++j)
        for (int i = 0; i < 11; ++i) {
          mx += w[j][i] / total * a.at(x0 + i, y0 + j);
          my += w[j][i] / total * b.at(x0 + i, y0 + j);
        }
      double vx = 0.0, vy = 0.0, cov = 0.0;
      for (int j = 0; j < 11; ++j)
        for (int i = 0; i < 11; ++i) {
          const double dx = a.at(x0 + i, y0 + j) - mx, dy = b.at(x0 + i, y0 + j) - my;
          vx += w[j][i] / total * dx * dx;
          vy += w[j][i] / total * dy * dy;
          cov += w[j][i] / total * dx * dy;
        }
      sum += (2.0 * mx * my + c1) * (2.0 * cov + c2) / ((mx * mx + my * my + c1) * (vx + vy + c2));
      ++windows;
    }
  return sum / windows;
}

TEST(PixelDifference, ClosedFormsOfShiftedAndSinglePixelChanges) {
  const Image8 a = grey(10, 10, 100);
  const PixelDifference same = pixelDifference(a, a);
  EXPECT_EQ(same.meanAbsolute, 0.0);
  EXPECT_EQ(same.shareOver8, 0.0);
  const PixelDifference by5 = pixelDifference(a, grey(10, 10, 105));
  EXPECT_DOUBLE_EQ(by5.meanAbsolute, 5.0);
  EXPECT_EQ(by5.shareOver8, 0.0);
  EXPECT_EQ(pixelDifference(a, grey(10, 10, 109)).shareOver8, 1.0);
  Image8 one = a;
  one.at(3, 4, 1) = 109;  // one channel of one pixel of 100, by 9
  const PixelDifference single = pixelDifference(a, one);
  EXPECT_DOUBLE_EQ(single.meanAbsolute, 9.0 / 300.0);
  EXPECT_DOUBLE_EQ(single.shareOver8, 0.01);
}

TEST(Ssim, IdenticalImagesAreOneAndConstantOnesTheLuminanceTerm) {
  const Image8 a = randomImage(40, 30, 4, 1);
  EXPECT_NEAR(meanSsim(a, a), 1.0, 1e-12);
  // Constant images: σ = 0, so the contrast-structure term is C2 / C2 and SSIM = (2ab + C1) / (a² + b² + C1).
  const double c1 = std::pow(0.01 * 255.0, 2.0);
  for (auto [x, y] : {std::pair{100, 150}, std::pair{0, 255}, std::pair{200, 201}})
    EXPECT_NEAR(meanSsim(grey(16, 12, x), grey(16, 12, y)), (2.0 * x * y + c1) / (x * x + y * y + c1), 1e-12) << x << " " << y;
}

TEST(Ssim, EqualsTheBruteForceOfThePapersDefinitions) {
  for (unsigned seed = 0; seed < 4; ++seed) {
    const Image8 a = randomImage(23, 17, 1, 2 * seed), noise = randomImage(23, 17, 1, 2 * seed + 1);
    // b: a mixed with noise (partly alike), and a inverted (anti-correlated: SSIM below 0).
    Image8 mixed = a, inverted = a;
    for (size_t p = 0; p < a.pixels.size(); ++p) {
      mixed.pixels[p] = static_cast<std::uint8_t>((3 * a.pixels[p] + noise.pixels[p]) / 4);
      inverted.pixels[p] = static_cast<std::uint8_t>(255 - a.pixels[p]);
    }
    EXPECT_NEAR(meanSsim(a, mixed), bruteForceSsim(a, mixed), 1e-9);
    EXPECT_NEAR(meanSsim(a, inverted), bruteForceSsim(a, inverted), 1e-9);
    EXPECT_LT(meanSsim(a, inverted), 0.0);
    EXPECT_DOUBLE_EQ(meanSsim(a, mixed), meanSsim(mixed, a));  // symmetric (eq. 13)
  }
}

TEST(Ssim, ColourImagesAreComparedByTheirLuma) {
  // Luma 0.2126 R + 0.7152 G + 0.0722 B: (0, 100, 0) and (0, 0, 0) have lumas 71.52 and 0.
  Image8 green(12, 12, 3), black(12, 12, 3);
  for (int y = 0; y < 12; ++y)
    for (int x = 0; x < 12; ++x) green.at(x, y, 1) = 100;
  const double c1 = std::pow(0.01 * 255.0, 2.0), luma = 71.52;
  EXPECT_NEAR(meanSsim(green, black), c1 / (luma * luma + c1), 1e-12);
}

// Masked: the pixels and windows of the mask alone. A change outside it leaves them as if the
// images were equal; inside, the closed forms of the whole image's case over the mask's pixels.
TEST(ImageDifference, AMaskComparesItsPixelsAndTheWindowsCentredOnThem) {
  const Image8 a = grey(20, 20, 100);
  Image8 b = a;
  std::vector<std::uint8_t> left(400, 0);
  for (int y = 0; y < 20; ++y)
    for (int x = 0; x < 20; ++x) {
      left[static_cast<size_t>(y * 20 + x)] = x < 10 ? 1 : 0;
      if (x >= 10) b.at(x, y, 0) = b.at(x, y, 1) = b.at(x, y, 2) = 130;  // the right half by 30
    }
  EXPECT_EQ(pixelDifference(a, b, left).meanAbsolute, 0.0);
  std::vector<std::uint8_t> right(left.size());
  for (size_t p = 0; p < left.size(); ++p) right[p] = left[p] ? 0 : 1;
  EXPECT_DOUBLE_EQ(pixelDifference(a, b, right).meanAbsolute, 30.0);
  EXPECT_DOUBLE_EQ(pixelDifference(a, b, right).shareOver8, 1.0);
  EXPECT_DOUBLE_EQ(pixelDifference(a, b).meanAbsolute, 15.0);
  EXPECT_EQ(pixelDifference(a, b, std::vector<std::uint8_t>(400, 0)).shareOver8, 0.0);  // no pixels: nothing differs
  // Windows centred on x < 5 lie in the equal half entirely: SSIM 1 there.
  std::vector<std::uint8_t> farLeft(400, 0);
  for (int y = 0; y < 20; ++y)
    for (int x = 0; x < 5; ++x) farLeft[static_cast<size_t>(y * 20 + x)] = 1;
  EXPECT_NEAR(meanSsim(a, b, farLeft), 1.0, 1e-12);
  for (unsigned seed = 0; seed < 3; ++seed) {
    const Image8 x = randomImage(23, 17, 1, 10 + seed), y = randomImage(23, 17, 1, 20 + seed);
    std::vector<std::uint8_t> mask(23 * 17);
    std::mt19937 rng(seed);
    for (std::uint8_t& m : mask) m = static_cast<std::uint8_t>(rng() % 3 == 0);
    EXPECT_NEAR(meanSsim(x, y, mask), bruteForceSsim(x, y, &mask), 1e-9);
  }
  EXPECT_THROW(pixelDifference(a, b, std::vector<std::uint8_t>(399, 1)), InputError);
  EXPECT_THROW(meanSsim(a, b, std::vector<std::uint8_t>(401, 1)), InputError);
}

TEST(Ssim, RefusesImagesItCannotCompare) {
  EXPECT_THROW(meanSsim(grey(16, 16, 0), grey(16, 15, 0)), InputError);
  EXPECT_THROW(meanSsim(grey(10, 16, 0), grey(10, 16, 0)), InputError);  // narrower than a window
  EXPECT_THROW(meanSsim(Image8(16, 16, 2), Image8(16, 16, 2)), InputError);
  EXPECT_THROW(pixelDifference(grey(4, 4, 0), grey(4, 5, 0)), InputError);
}

}  // namespace
}  // namespace forest
