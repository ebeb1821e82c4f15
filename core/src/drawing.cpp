#include "forest/core/drawing.hpp"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <algorithm>
#include <cmath>

#include "forest/core/error.hpp"

namespace forest {
namespace {

// An ImageBuf over the image's own pixels (no copy).
OIIO::ImageBuf wrap(Image8& image) {
  if (image.channels != 3 && image.channels != 4) throw Error("drawing: expected an RGB or RGBA image");
  return OIIO::ImageBuf(OIIO::ImageSpec(image.width, image.height, image.channels, OIIO::TypeDesc::UINT8), image.pixels.data());
}

// The colour per channel of the image; opaque where the image has alpha.
OIIO::cspan<float> inkFor(const Image8& image, glm::vec3 colour, float (&ink)[4]) {
  ink[0] = colour.r;
  ink[1] = colour.g;
  ink[2] = colour.b;
  ink[3] = 1.0f;
  return OIIO::cspan<float>(ink, static_cast<size_t>(image.channels));
}

int pixel(double v) { return static_cast<int>(std::lround(std::clamp(v, -1e6, 1e6))); }

}  // namespace

void drawLine(Image8& image, glm::dvec2 a, glm::dvec2 b, glm::vec3 colour) {
  OIIO::ImageBuf buffer = wrap(image);
  float ink[4];
  OIIO::ImageBufAlgo::render_line(buffer, pixel(a.x), pixel(a.y), pixel(b.x), pixel(b.y), inkFor(image, colour, ink));
}

void drawPolygon(Image8& image, std::span<const glm::dvec2> polygon, glm::vec3 colour) {
  for (size_t i = 0; i < polygon.size(); ++i) drawLine(image, polygon[i], polygon[(i + 1) % polygon.size()], colour);
}

void fillConvexPolygon(Image8& image, std::span<const glm::dvec2> polygon, glm::vec3 colour, float opacity) {
  if (polygon.size() < 3) return;
  double top = polygon[0].y, bottom = polygon[0].y;
  for (const glm::dvec2& p : polygon) {
    top = std::min(top, p.y);
    bottom = std::max(bottom, p.y);
  }
  const int y0 = std::max(0, static_cast<int>(std::ceil(top - 0.5))), y1 = std::min(image.height - 1, static_cast<int>(std::floor(bottom - 0.5)));
  for (int y = y0; y <= y1; ++y) {
    // Scanline through pixel centres: the span between the polygon's edge crossings.
    const double sy = y + 0.5;
    double left = 1e300, right = -1e300;
    for (size_t i = 0; i < polygon.size(); ++i) {
      const glm::dvec2 a = polygon[i], b = polygon[(i + 1) % polygon.size()];
      if ((a.y <= sy) == (b.y <= sy)) continue;
      const double x = a.x + (sy - a.y) / (b.y - a.y) * (b.x - a.x);
      left = std::min(left, x);
      right = std::max(right, x);
    }
    const int x0 = std::max(0, static_cast<int>(std::ceil(left - 0.5))), x1 = std::min(image.width - 1, static_cast<int>(std::floor(right - 0.5)));
    for (int x = x0; x <= x1; ++x)
      for (int c = 0; c < 3; ++c) {
        const float blended = (1.0f - opacity) * image.at(x, y, c) + opacity * 255.0f * colour[c];
        image.at(x, y, c) = static_cast<std::uint8_t>(std::clamp(blended + 0.5f, 0.0f, 255.0f));
      }
  }
}

bool drawText(Image8& image, glm::ivec2 at, std::string_view text, glm::vec3 colour, int size) {
  OIIO::ImageBuf buffer = wrap(image);
  float ink[4];
  const bool drawn = OIIO::ImageBufAlgo::render_text(buffer, at.x, at.y, text, size, "DejaVuSans", inkFor(image, colour, ink));
  if (!drawn) (void)buffer.geterror();  // no font: leave the image as it was
  return drawn;
}

void paste(Image8& target, const Image8& source, glm::ivec2 at) {
  if (target.channels != source.channels) throw Error("paste: expected images with the same channels");
  for (int y = std::max(0, -at.y); y < source.height && at.y + y < target.height; ++y)
    for (int x = std::max(0, -at.x); x < source.width && at.x + x < target.width; ++x)
      for (int c = 0; c < source.channels; ++c) target.at(at.x + x, at.y + y, c) = source.at(x, y, c);
}

}  // namespace forest
