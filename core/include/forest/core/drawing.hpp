#pragma once
// Drawing on 8-bit RGB or RGBA images (drawn pixels become opaque) for diagrams and overlays (OpenImageIO's ImageBufAlgo): lines, filled and
// outlined polygons, text. Coordinates are pixels, x right, y down; anything outside is clipped.
#include <glm/glm.hpp>

#include <span>
#include <string_view>

#include "forest/core/image.hpp"

namespace forest {

void drawLine(Image8& image, glm::dvec2 a, glm::dvec2 b, glm::vec3 colour);
// Outline of a closed polygon.
void drawPolygon(Image8& image, std::span<const glm::dvec2> polygon, glm::vec3 colour);
// Fills a convex polygon, blended over the image with the given opacity.
void fillConvexPolygon(Image8& image, std::span<const glm::dvec2> polygon, glm::vec3 colour, float opacity);
// Text with its baseline starting at `at`, DejaVu Sans (fonts-dejavu-core). Returns false when no
// font is available (the image is left as it was).
bool drawText(Image8& image, glm::ivec2 at, std::string_view text, glm::vec3 colour, int size = 14);
// Copies `source` into `target` with its top-left corner at `at` (same channel count; clipped).
void paste(Image8& target, const Image8& source, glm::ivec2 at);

}  // namespace forest
