#include "forest/core/image_difference.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <vector>

#include "forest/core/error.hpp"

namespace forest {
namespace {

constexpr int kWindow = 11;          // Wang et al. 2004 §III-C: 11 × 11 Gaussian, σ = 1.5
constexpr double kWindowSigma = 1.5;
constexpr double kC1 = (0.01 * 255.0) * (0.01 * 255.0);  // eq. 7: (K1 L)², K1 = 0.01, L = 255
constexpr double kC2 = (0.03 * 255.0) * (0.03 * 255.0);  // eq. 10: (K2 L)², K2 = 0.03

void requireSameSize(const Image8& a, const Image8& b, const char* what) {
  if (a.width != b.width || a.height != b.height || a.channels != b.channels)
    throw InputError(fmt::format("{}: images of {}x{}x{} and {}x{}x{}: expected the same size and channels", what, a.width, a.height,
                                 a.channels, b.width, b.height, b.channels));
}

// One image's luma, row-major.
std::vector<double> lumaOf(const Image8& image) {
  std::vector<double> y(static_cast<size_t>(image.width) * image.height);
  for (size_t p = 0; p < y.size(); ++p) {
    const std::uint8_t* c = &image.pixels[p * static_cast<size_t>(image.channels)];
    y[p] = image.channels == 1 ? c[0] : 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
  }
  return y;
}

// The separable window's weights: w(i) ∝ exp(−i² / 2σ²), i = −5 … 5, the 2D window w(i) w(j)
// summing to 1.
std::array<double, kWindow> windowWeights() {
  std::array<double, kWindow> w{};
  double sum = 0.0;
  for (int i = 0; i < kWindow; ++i) {
    const double d = i - kWindow / 2;
    w[static_cast<size_t>(i)] = std::exp(-d * d / (2.0 * kWindowSigma * kWindowSigma));
    sum += w[static_cast<size_t>(i)];
  }
  for (double& v : w) v /= sum;
  return w;
}

// The window-weighted mean of `v` at every window inside the image ((w − 10) × (h − 10) values):
// the rows filtered, then the columns.
std::vector<double> windowed(const std::vector<double>& v, int width, int height) {
  static const std::array<double, kWindow> w = windowWeights();
  const int outW = width - kWindow + 1, outH = height - kWindow + 1;
  std::vector<double> rows(static_cast<size_t>(outW) * height), out(static_cast<size_t>(outW) * outH);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < outW; ++x) {
      double s = 0.0;
      for (int k = 0; k < kWindow; ++k) s += w[static_cast<size_t>(k)] * v[static_cast<size_t>(y) * width + x + k];
      rows[static_cast<size_t>(y) * outW + x] = s;
    }
  for (int y = 0; y < outH; ++y)
    for (int x = 0; x < outW; ++x) {
      double s = 0.0;
      for (int k = 0; k < kWindow; ++k) s += w[static_cast<size_t>(k)] * rows[static_cast<size_t>(y + k) * outW + x];
      out[static_cast<size_t>(y) * outW + x] = s;
    }
  return out;
}

void requireMask(const Image8& a, const std::vector<std::uint8_t>* mask, const char* what) {
  if (mask && mask->size() != static_cast<size_t>(a.width) * a.height)
    throw InputError(fmt::format("{}: a mask of {} bytes for {}x{} pixels: expected one a pixel", what, mask->size(), a.width, a.height));
}

PixelDifference maskedPixelDifference(const Image8& a, const Image8& b, const std::vector<std::uint8_t>* mask) {
  requireSameSize(a, b, "pixel difference");
  requireMask(a, mask, "pixel difference");
  if (a.channels != 3 && a.channels != 4) throw InputError(fmt::format("pixel difference: {} channels, expected 3 or 4", a.channels));
  double sum = 0.0;
  long long differing = 0, counted = 0;
  const size_t pixels = static_cast<size_t>(a.width) * a.height, step = static_cast<size_t>(a.channels);
  for (size_t p = 0; p < pixels; ++p) {
    if (mask && !(*mask)[p]) continue;
    ++counted;
    int largest = 0;
    for (size_t c = 0; c < 3; ++c) {
      const int d = std::abs(a.pixels[p * step + c] - b.pixels[p * step + c]);
      sum += d;
      largest = std::max(largest, d);
    }
    differing += largest > 8 ? 1 : 0;
  }
  const double n = std::max<double>(1.0, static_cast<double>(counted));
  return {sum / (3.0 * n), static_cast<double>(differing) / n};
}

double maskedSsim(const Image8& a, const Image8& b, const std::vector<std::uint8_t>* mask) {
  requireSameSize(a, b, "SSIM");
  requireMask(a, mask, "SSIM");
  if (a.channels != 1 && a.channels != 3 && a.channels != 4) throw InputError(fmt::format("SSIM: {} channels, expected 1, 3 or 4", a.channels));
  if (a.width < kWindow || a.height < kWindow)
    throw InputError(fmt::format("SSIM: {}x{} pixels, expected at least {}x{} (one window)", a.width, a.height, kWindow, kWindow));
  const std::vector<double> x = lumaOf(a), y = lumaOf(b);
  std::vector<double> xx(x.size()), yy(x.size()), xy(x.size());
  for (size_t p = 0; p < x.size(); ++p) {
    xx[p] = x[p] * x[p];
    yy[p] = y[p] * y[p];
    xy[p] = x[p] * y[p];
  }
  const std::vector<double> mx = windowed(x, a.width, a.height), my = windowed(y, a.width, a.height);
  const std::vector<double> sxx = windowed(xx, a.width, a.height), syy = windowed(yy, a.width, a.height), sxy = windowed(xy, a.width, a.height);
  double sum = 0.0;
  long long windows = 0;
  const int outW = a.width - kWindow + 1;
  for (size_t i = 0; i < mx.size(); ++i) {
    const int x0 = static_cast<int>(i % static_cast<size_t>(outW)), y0 = static_cast<int>(i / static_cast<size_t>(outW));
    if (mask && !(*mask)[static_cast<size_t>(y0 + kWindow / 2) * a.width + x0 + kWindow / 2]) continue;  // its centre pixel
    ++windows;
    // Eq. 14–16 with weights summing to 1: σ² = E[x²] − μ², σxy = E[xy] − μx μy.
    const double varX = sxx[i] - mx[i] * mx[i], varY = syy[i] - my[i] * my[i], cov = sxy[i] - mx[i] * my[i];
    sum += (2.0 * mx[i] * my[i] + kC1) * (2.0 * cov + kC2) / ((mx[i] * mx[i] + my[i] * my[i] + kC1) * (varX + varY + kC2));
  }
  return windows > 0 ? sum / static_cast<double>(windows) : 1.0;
}

}  // namespace

PixelDifference pixelDifference(const Image8& a, const Image8& b) { return maskedPixelDifference(a, b, nullptr); }
PixelDifference pixelDifference(const Image8& a, const Image8& b, const std::vector<std::uint8_t>& mask) {
  return maskedPixelDifference(a, b, &mask);
}
double meanSsim(const Image8& a, const Image8& b) { return maskedSsim(a, b, nullptr); }
double meanSsim(const Image8& a, const Image8& b, const std::vector<std::uint8_t>& mask) { return maskedSsim(a, b, &mask); }

}  // namespace forest
