#include "forest/render/debug_views.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "forest/core/drawing.hpp"
#include "forest/core/polygon2d.hpp"
#include "forest/shadows/focus_body.hpp"

namespace forest::render {
namespace {

using glm::dvec2;
using glm::dvec3;

const glm::vec3 kBackground{0.97f, 0.97f, 0.95f}, kView{0.0f, 0.0f, 0.0f}, kBody{0.15f, 0.35f, 0.9f},
    kLight{0.85f, 0.1f, 0.1f}, kReceiver{0.2f, 0.7f, 0.25f}, kCaster{0.95f, 0.55f, 0.05f};

std::vector<dvec2> footprint(const std::vector<dvec3>& points) {
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

Image8 topDownDiagram(const Frame& frame, const dvec3& sunDirection, int size) {
  Image8 image(size, size, 3);
  for (size_t i = 0; i < image.pixels.size(); ++i) image.pixels[i] = static_cast<std::uint8_t>(255.0f * kBackground[static_cast<int>(i % 3)]);
  const shadows::ShadowSetup& setup = frame.shadowSetup();
  const std::vector<dvec2> view = footprint(shadows::viewFrustumBody(frame.shadowCamera()).vertices());
  const std::vector<dvec2> body = footprint(setup.body.vertices());
  std::vector<dvec3> lightCorners;
  if (!setup.empty)
    for (const dvec3& c : lightFrustumCorners(setup)) lightCorners.push_back(c);
  const std::vector<dvec2> light = footprint(lightCorners);

  // The drawn region: V and B (the light frustum may reach far beyond; it is clipped).
  dvec2 low(1e300), high(-1e300);
  for (const auto* polygon : {&view, &body})
    for (const dvec2& p : *polygon) {
      low = glm::min(low, p);
      high = glm::max(high, p);
    }
  if (!(high.x > low.x) || !(high.y > low.y)) {
    low = dvec2(frame.shadowCamera().position.x, frame.shadowCamera().position.z) - 1.0;
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

  const auto& boxes = frame.objects().boxes();
  for (std::uint32_t o : frame.visibleObjects()) fillConvexPolygon(image, boxOutline(boxes[o]), kReceiver, 0.35f);
  fillConvexPolygon(image, mapped(body), kBody, 0.18f);
  for (std::uint32_t o : frame.casters()) drawPolygon(image, boxOutline(boxes[o]), kCaster);
  drawPolygon(image, mapped(body), kBody);
  drawPolygon(image, mapped(light), kLight);
  drawPolygon(image, mapped(view), kView);
  const dvec3 eye = frame.shadowCamera().position;
  const dvec2 eyePixel = toPixel({eye.x, eye.z});
  fillConvexPolygon(image, std::vector<dvec2>{eyePixel + dvec2(-4, -4), eyePixel + dvec2(4, -4), eyePixel + dvec2(4, 4), eyePixel + dvec2(-4, 4)},
                    kView, 1.0f);
  // The sun: an arrow along the way the light travels (horizontal part), top-right corner.
  const dvec2 across(sunDirection.x, sunDirection.z);
  const dvec2 centre(size - 50.0, 50.0);
  if (glm::length(across) > 1e-6 * glm::length(sunDirection)) {
    const dvec2 d = glm::normalize(across), side(-d.y, d.x);
    drawLine(image, centre - 30.0 * d, centre + 30.0 * d, kLight);
    drawLine(image, centre + 30.0 * d, centre + 18.0 * d + 7.0 * side, kLight);
    drawLine(image, centre + 30.0 * d, centre + 18.0 * d - 7.0 * side, kLight);
  }
  drawText(image, {size - 90, 100}, "light", kLight, 14);
  int y = 20;
  for (const auto& [text, colour] : {std::pair{"view frustum to z_f", kView}, std::pair{"focus body B", kBody},
                                     std::pair{"light frustum (map)", kLight}, std::pair{"visible receivers", kReceiver},
                                     std::pair{"selected casters", kCaster}}) {
    drawText(image, {10, y}, text, colour, 14);
    y += 18;
  }
  drawText(image, {10, size - 10},
           fmt::format("{} visible, {} casters; {:.0f} m across; x right, z down", frame.visibleObjects().size(),
                       frame.casters().size(), (size - 2.0 * margin) / scale),
           kView, 14);
  return image;
}

}  // namespace forest::render
