#include "forest/render/debug_views.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <span>
#include <string>

#include "forest/core/drawing.hpp"
#include "forest/core/polygon2d.hpp"
#include "forest/shadows/focus_body.hpp"

namespace forest::render {
namespace {

using glm::dvec2;
using glm::dvec3;

const glm::vec3 kBackground{0.97f, 0.97f, 0.95f}, kView{0.0f, 0.0f, 0.0f}, kBody{0.15f, 0.35f, 0.9f},
    kLight{0.85f, 0.1f, 0.1f}, kReceiver{0.2f, 0.7f, 0.25f}, kCaster{0.95f, 0.55f, 0.05f};

const glm::vec3 kText{0.1f, 0.1f, 0.1f};
// Slices 0–3 of a z-partitioned frame: B and light frustum in the top-down diagram, the tint of
// their pixels in the slices picture.
const glm::vec3 kSlice[shadows::kMaxCascades] = {{0.15f, 0.35f, 0.9f}, {0.1f, 0.65f, 0.65f}, {0.6f, 0.25f, 0.8f}, {0.85f, 0.1f, 0.1f}};

Image8 filled(int width, int height, glm::vec3 colour) {
  Image8 image(width, height, 3);
  for (size_t i = 0; i < image.pixels.size(); ++i) image.pixels[i] = static_cast<std::uint8_t>(255.0f * colour[static_cast<int>(i % 3)]);
  return image;
}

std::vector<dvec2> footprint(std::span<const dvec3> points) {
  std::vector<dvec2> xz;
  for (const dvec3& p : points) xz.emplace_back(p.x, p.z);
  return convexHull(std::move(xz));
}

}  // namespace

std::array<dvec3, 8> lightFrustumCorners(const shadows::ShadowSetup& setup) {
  const glm::dmat4& m = setup.worldToShadowClip;
  auto row = [&](int r) { return glm::dvec4(m[0][r], m[1][r], m[2][r], m[3][r]); };
  std::array<dvec3, 8> corners;
  for (int i = 0; i < 8; ++i) {
    const dvec3 c((i & 1) ? 1.0 : -1.0, (i & 2) ? 1.0 : -1.0, (i & 4) ? 1.0 : -1.0);
    // Three planes through the corner: x = X·w, y = Y·w, and depth = Z (linear) or z = Z·w.
    const glm::dvec4 planes[3] = {row(0) - c.x * row(3), row(1) - c.y * row(3),
                                  setup.linearDepth ? setup.worldToLightDepth - glm::dvec4(0, 0, 0, c.z) : row(2) - c.z * row(3)};
    glm::dmat3 a;
    glm::dvec3 b;
    for (int k = 0; k < 3; ++k) {
      for (int j = 0; j < 3; ++j) a[j][k] = planes[k][j];
      b[k] = -planes[k].w;
    }
    corners[static_cast<size_t>(i)] = glm::inverse(a) * b;
  }
  return corners;
}

namespace {

// The top-down diagram's legend band: what each colour is, the counts, the scale and an arrow the
// way the light travels.
Image8 topDownLegend(const Frame& frame, const dvec3& sunDirection, int size, bool lightClipped, size_t casters, double metresAcross) {
  const int slices = frame.cascadeCount();
  Image8 legend = filled(size, kTopDownLegendHeight, kBackground);
  int y = 18;
  const std::string clipped = lightClipped ? "; clipped at the frame" : "";
  std::vector<std::pair<std::string, glm::vec3>> entries{{"view frustum to z_f", kView}};
  if (slices == 1) {
    entries.emplace_back("focus body B", kBody);
    entries.emplace_back("light frustum (map" + clipped + ")", kLight);
  }
  entries.emplace_back("visible receivers", kReceiver);
  entries.emplace_back("selected casters", kCaster);
  for (const auto& [text, colour] : entries) {
    drawText(legend, {10, y}, text, colour, 14);
    y += 18;
  }
  for (int i = 0; i < slices && slices > 1; ++i)  // one line per slice in the middle column
    drawText(legend, {size / 2 - 60, 54 + 18 * i},
             fmt::format("slice {}: B and light frustum{}", i, i == 0 && lightClipped ? " (frusta clipped at the frame)" : ""), kSlice[i], 14);
  drawText(legend, {size / 2 - 60, 18}, fmt::format("{} visible, {} casters", frame.visibleObjects().size(), casters), kView, 14);
  drawText(legend, {size / 2 - 60, 36}, fmt::format("{:.0f} m across; x right, z down", metresAcross), kView, 14);
  // The sun: an arrow along the way the light travels (its horizontal part).
  const dvec2 across(sunDirection.x, sunDirection.z);
  const dvec2 centre(size - 60.0, 50.0);
  if (glm::length(across) > 1e-6 * glm::length(sunDirection)) {
    const dvec2 d = glm::normalize(across), side(-d.y, d.x);
    drawLine(legend, centre - 30.0 * d, centre + 30.0 * d, kLight);
    drawLine(legend, centre + 30.0 * d, centre + 18.0 * d + 7.0 * side, kLight);
    drawLine(legend, centre + 30.0 * d, centre + 18.0 * d - 7.0 * side, kLight);
  }
  drawText(legend, {size - 80, kTopDownLegendHeight - 8}, "light", kLight, 14);
  return legend;
}

}  // namespace

Image8 topDownDiagram(const Frame& frame, const dvec3& sunDirection, int size) {
  Image8 image = filled(size, size, kBackground);  // the diagram; the legend band goes on top at the end
  const int slices = frame.cascadeCount();
  Camera whole = frame.shadowCamera(0);  // the view from the first slice's near to the last one's far
  whole.far = frame.shadowCamera(slices - 1).far;
  const std::vector<dvec2> view = footprint(shadows::viewFrustumBody(whole).vertices());
  std::vector<std::vector<dvec2>> bodies, lights;
  for (int i = 0; i < slices; ++i) {
    const shadows::ShadowSetup& setup = frame.shadowSetup(i);
    bodies.push_back(footprint(setup.body.vertices()));
    std::vector<dvec3> lightCorners;
    if (!setup.empty)
      for (const dvec3& c : lightFrustumCorners(setup)) lightCorners.push_back(c);
    lights.push_back(footprint(lightCorners));
  }

  // The drawn region: V and the bodies (a light frustum may reach far beyond; it is clipped).
  dvec2 low(1e300), high(-1e300);
  for (const dvec2& p : view) {
    low = glm::min(low, p);
    high = glm::max(high, p);
  }
  for (const auto& body : bodies)
    for (const dvec2& p : body) {
      low = glm::min(low, p);
      high = glm::max(high, p);
    }
  if (!(high.x > low.x) || !(high.y > low.y)) {
    low = dvec2(whole.position.x, whole.position.z) - 1.0;
    high = low + 2.0;
  }
  const double margin = 0.06 * size, scale = (size - 2.0 * margin) / std::max(high.x - low.x, high.y - low.y);
  auto toPixel = [&](const dvec2& p) { return margin + (p - low) * scale; };
  auto mapped = [&](const std::vector<dvec2>& polygon) {
    std::vector<dvec2> out;
    for (const dvec2& p : polygon) out.push_back(toPixel(p));
    return out;
  };
  auto boxOutline = [&](const Aabb& box) {
    return std::vector<dvec2>{toPixel({box.min.x, box.min.z}), toPixel({box.max.x, box.min.z}), toPixel({box.max.x, box.max.z}),
                              toPixel({box.min.x, box.max.z})};
  };
  // One map: B blue and the light frustum red; slices: each its own colour for both.
  auto bodyColour = [&](int i) { return slices == 1 ? kBody : kSlice[i]; };
  auto lightColour = [&](int i) { return slices == 1 ? kLight : kSlice[i]; };

  const auto& boxes = frame.objects().boxes();
  for (std::uint32_t o : frame.visibleObjects()) fillConvexPolygon(image, boxOutline(boxes[o]), kReceiver, 0.35f);
  for (int i = 0; i < slices; ++i) fillConvexPolygon(image, mapped(bodies[static_cast<size_t>(i)]), bodyColour(i), 0.18f);
  size_t casters = 0;
  for (int i = 0; i < slices; ++i) {
    const std::vector<std::uint32_t> drawn = frame.casters(i);
    for (std::uint32_t o : drawn) drawPolygon(image, boxOutline(boxes[o]), kCaster);
    casters += drawn.size();
  }
  for (int i = 0; i < slices; ++i) {
    drawPolygon(image, mapped(bodies[static_cast<size_t>(i)]), bodyColour(i));
    drawPolygon(image, mapped(lights[static_cast<size_t>(i)]), lightColour(i));
  }
  drawPolygon(image, mapped(view), kView);
  const dvec3 eye = whole.position;
  const dvec2 eyePixel = toPixel({eye.x, eye.z});
  fillConvexPolygon(image, std::vector<dvec2>{eyePixel + dvec2(-4, -4), eyePixel + dvec2(4, -4), eyePixel + dvec2(4, 4), eyePixel + dvec2(-4, 4)},
                    kView, 1.0f);
  drawPolygon(image, std::vector<dvec2>{{0, 0}, {size - 1, 0}, {size - 1, size - 1}, {0, size - 1}}, kView);

  // The legend band: what each colour is, the scale, and the way the light travels.
  const bool lightClipped = std::any_of(lights.begin(), lights.end(), [&](const std::vector<dvec2>& light) {
    return std::any_of(light.begin(), light.end(), [&](const dvec2& p) {
      const dvec2 q = toPixel(p);
      return q.x < 0.0 || q.y < 0.0 || q.x > size || q.y > size;
    });
  });
  const Image8 legend = topDownLegend(frame, sunDirection, size, lightClipped, casters, (size - 2.0 * margin) / scale);
  Image8 result(size, kTopDownLegendHeight + size, 3);
  paste(result, legend, {0, 0});
  paste(result, image, {0, kTopDownLegendHeight});
  return result;
}

Image8 cascadesPicture(const Frame& frame, const Camera& camera, const FrameStats& stats) {
  const Image8 tinted = frame.readColor();
  Image8 image = filled(tinted.width, tinted.height + kCascadesLegendHeight, kBackground);
  for (int y = 0; y < tinted.height; ++y)
    for (int x = 0; x < tinted.width; ++x)
      for (int c = 0; c < 3; ++c) image.at(x, y, c) = tinted.at(x, y, c);
  const std::vector<float> depth = frame.readDepth();  // bottom row first, reversed-Z
  std::array<long long, shadows::kMaxCascades> pixels{};
  for (int y = 0; y < tinted.height; ++y)
    for (int x = 0; x < tinted.width; ++x) {
      const float d = depth[static_cast<size_t>(tinted.height - 1 - y) * tinted.width + x];
      if (!(d > 0.0f)) continue;  // sky
      const double z = camera.eyeDepthOfReversedZ(d);
      const int slice = frame.cascadeOf(z);
      ++pixels[static_cast<size_t>(slice)];
      for (int c = 0; c < 3; ++c)
        image.at(x, y, c) = static_cast<std::uint8_t>(std::lround(0.5f * image.at(x, y, c) + 0.5f * 255.0f * kSlice[slice][c]));
    }
  // The legend: one swatch and line per slice, side by side.
  const int slices = std::max(1, stats.cascades), column = image.width / slices;
  const double total = static_cast<double>(tinted.width) * tinted.height;
  for (int i = 0; i < slices; ++i) {
    const CascadeStats& s = stats.cascade[static_cast<size_t>(i)];
    const int left = i * column + 6, top = tinted.height + 6;
    for (int y = top; y < top + 12; ++y)
      for (int x = left; x < left + 12; ++x)
        for (int c = 0; c < 3; ++c) image.at(x, y, c) = static_cast<std::uint8_t>(255.0f * kSlice[i][c]);
    drawText(image, {left + 16, top + 11}, fmt::format("slice {}: {:.1f}-{:.0f} m, {:.0f}% px", i, s.fromM, s.toM, 100.0 * static_cast<double>(pixels[static_cast<size_t>(i)]) / total),
             kText, 11);
  }
  return image;
}

Image8 captionedTerm(const std::vector<float>& term, int width, int height, const std::string& caption) {
  Image8 image = filled(width, height + kCaptionHeight, kBackground);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const float v = term[static_cast<size_t>(height - 1 - y) * width + x];  // top row first
      const auto grey = static_cast<std::uint8_t>(v > 0.0f ? std::lround(std::min(v, 1.0f) * 255.0f) : 0);
      for (int c = 0; c < 3; ++c) image.at(x, y, c) = grey;
    }
  drawText(image, {6, height + kCaptionHeight - 6}, caption, kText, 12);
  return image;
}

Image8 shadowMapPicture(const std::vector<float>& depth, int size) {
  const glm::vec3 kNoCaster{0.78f, 0.86f, 0.97f};
  // The range of the drawn texels (the clear value 1 marks texels no caster reached).
  double lo = 1.0, hi = 0.0;
  size_t drawn = 0;
  for (float v : depth)
    if (std::isfinite(v) && v < 1.0f) {
      lo = std::min(lo, double(v));
      hi = std::max(hi, double(v));
      ++drawn;
    }
  const double scale = hi > lo ? 1.0 / (hi - lo) : 0.0;
  auto grey = [&](double v) { return static_cast<std::uint8_t>(std::lround(std::clamp((v - lo) * scale, 0.0, 1.0) * 235.0 + 10.0)); };
  Image8 image = filled(size, size + kShadowMapLegendHeight, kBackground);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const float v = depth[static_cast<size_t>(size - 1 - y) * size + x];  // top row first
      for (int c = 0; c < 3; ++c)
        image.at(x, y, c) = std::isfinite(v) && v < 1.0f ? grey(v) : static_cast<std::uint8_t>(255.0f * kNoCaster[c]);
    }
  // The scale: a ramp from the nearest to the farthest drawn depth, and the no-caster colour.
  const int rampLeft = 8, rampRight = size / 2, rampTop = size + 6, rampBottom = size + 18;
  for (int x = rampLeft; x < rampRight; ++x)
    for (int y = rampTop; y < rampBottom; ++y)
      for (int c = 0; c < 3; ++c) image.at(x, y, c) = grey(lo + (hi - lo) * (x - rampLeft) / double(rampRight - rampLeft - 1));
  const int textSize = std::clamp(size / 48, 9, 14);
  drawText(image, {rampLeft, size + kShadowMapLegendHeight - 6},
           drawn == 0 ? std::string("no caster drawn") : fmt::format("light depth {:.4f} (near the light) to {:.4f}", lo, hi), kText, textSize);
  for (int x = rampRight + 12; x < rampRight + 28; ++x)
    for (int y = rampTop; y < rampBottom; ++y)
      for (int c = 0; c < 3; ++c) image.at(x, y, c) = static_cast<std::uint8_t>(255.0f * kNoCaster[c]);
  drawText(image, {rampRight + 34, rampBottom},
           fmt::format("no caster (casters cover {:.1f}% of the map)", 100.0 * double(drawn) / std::max<double>(1.0, double(depth.size()))), kText,
           textSize);
  return image;
}

}  // namespace forest::render
