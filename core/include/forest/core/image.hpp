#pragma once
// Images in memory and on disk (OpenImageIO). Rows are stored top to bottom; GL read-backs
// (bottom to top) are flipped with flipRows() before they are written.
#include <cstdint>
#include <filesystem>
#include <vector>

namespace forest {

template <typename T>
struct Image {
  int width = 0;
  int height = 0;
  int channels = 0;
  std::vector<T> pixels;  // width * height * channels, row-major, top row first

  Image() = default;
  Image(int w, int h, int c) : width(w), height(h), channels(c), pixels(static_cast<size_t>(w) * h * c) {}
  T& at(int x, int y, int c = 0) { return pixels[(static_cast<size_t>(y) * width + x) * channels + c]; }
  const T& at(int x, int y, int c = 0) const {
    return pixels[(static_cast<size_t>(y) * width + x) * channels + c];
  }
  bool empty() const { return pixels.empty(); }
};

using Image8 = Image<std::uint8_t>;
using ImageF = Image<float>;

// Reverses the row order in place.
template <typename T>
void flipRows(Image<T>& image) {
  const size_t row = static_cast<size_t>(image.width) * image.channels;
  for (int y = 0; y < image.height / 2; ++y) {
    auto top = image.pixels.begin() + static_cast<std::ptrdiff_t>(y * row);
    auto bottom = image.pixels.begin() + static_cast<std::ptrdiff_t>((image.height - 1 - y) * row);
    std::swap_ranges(top, top + static_cast<std::ptrdiff_t>(row), bottom);
  }
}

// Writes 8-bit images (PNG, or any format OpenImageIO knows from the extension) atomically.
void writeImage(const std::filesystem::path& file, const Image8& image);
// Writes float images (EXR keeps full float; other formats are quantised) atomically.
void writeImage(const std::filesystem::path& file, const ImageF& image);
// Reads any OpenImageIO-readable image, converting to the requested pixel type.
Image8 readImage8(const std::filesystem::path& file);
ImageF readImageF(const std::filesystem::path& file);

}  // namespace forest
