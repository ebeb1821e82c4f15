#include "forest/core/plot.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "forest/core/drawing.hpp"

namespace forest {
namespace {

// A "nice" tick step (1, 2 or 5 × 10^k) giving about `count` ticks over `range`.
double tickStep(double range, int count) {
  const double raw = range / count, power = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * power >= raw) return m * power;
  return 10.0 * power;
}

std::string tickLabel(double v, double step) {
  const int decimals = std::clamp(static_cast<int>(-std::floor(std::log10(step))), 0, 6);
  return fmt::format("{:.{}f}", v, decimals);
}

// The highest finite y of a series (−∞ for none).
double peakOf(const PlotSeries& s) {
  double peak = -std::numeric_limits<double>::infinity();
  for (const glm::dvec2& p : s.points)
    if (std::isfinite(p.x) && std::isfinite(p.y)) peak = std::max(peak, p.y);
  return peak;
}

// The median of a series' finite y values (the upper one of an even count); −∞ for none.
double levelOf(const PlotSeries& s) {
  std::vector<double> ys;
  for (const glm::dvec2& p : s.points)
    if (std::isfinite(p.x) && std::isfinite(p.y)) ys.push_back(p.y);
  if (ys.empty()) return -std::numeric_limits<double>::infinity();
  std::nth_element(ys.begin(), ys.begin() + static_cast<std::ptrdiff_t>(ys.size() / 2), ys.end());
  return ys[ys.size() / 2];
}

// An arrow at the top edge where a clipped point lies above it.
void markClipped(Image8& image, const glm::dvec2& at, const glm::vec3& colour) {
  fillConvexPolygon(image, std::vector<glm::dvec2>{at + glm::dvec2(-5, 4), at + glm::dvec2(5, 4), at + glm::dvec2(0, -5)}, colour, 1.0f);
}

void drawPanel(Image8& image, const PlotPanel& panel, int left, int top, int width, int height) {
  // The title above the y axis's label, which stands above the plot area.
  const int x0 = left + 70, x1 = left + width - 20, y0 = top + 54, y1 = top + height - 50;  // plot area
  glm::dvec2 low(1e300), high(-1e300);
  for (const PlotSeries& s : panel.series)
    for (const glm::dvec2& p : s.points)
      if (std::isfinite(p.x) && std::isfinite(p.y)) {
        low = glm::min(low, p);
        high = glm::max(high, p);
      }
  drawText(image, {x0, top + 22}, panel.title, glm::vec3(0.0f), 15);
  if (!(high.x >= low.x)) {
    drawText(image, {x0 + 10, (y0 + y1) / 2}, "no data", glm::vec3(0.4f), 14);
    return;
  }
  low.x = std::min(low.x, 0.0);  // errors and times start at 0
  if (!(high.x > low.x)) high.x = low.x + 1.0;
  high.x += 0.05 * (high.x - low.x);
  const PlotYRange yRange = plotYRange(panel);
  low.y = yRange.low;
  high.y = yRange.high;
  auto toPixel = [&](const glm::dvec2& p) {
    return glm::dvec2(x0 + (p.x - low.x) / (high.x - low.x) * (x1 - x0), y1 - (p.y - low.y) / (high.y - low.y) * (y1 - y0));
  };
  const glm::vec3 axis(0.2f), grid(0.88f);
  for (int a = 0; a < 2; ++a) {
    const double step = tickStep(high[a] - low[a], 5);
    for (double v = std::ceil(low[a] / step) * step; v <= high[a]; v += step) {
      const glm::dvec2 p = toPixel(a == 0 ? glm::dvec2(v, low.y) : glm::dvec2(low.x, v));
      if (a == 0) {
        drawLine(image, {p.x, double(y0)}, {p.x, double(y1)}, grid);
        drawText(image, {static_cast<int>(p.x) - 12, y1 + 18}, tickLabel(v, step), axis, 12);
      } else {
        drawLine(image, {double(x0), p.y}, {double(x1), p.y}, grid);
        drawText(image, {left + 8, static_cast<int>(p.y) + 4}, tickLabel(v, step), axis, 12);
      }
    }
  }
  drawLine(image, {double(x0), double(y1)}, {double(x1), double(y1)}, axis);
  drawLine(image, {double(x0), double(y0)}, {double(x0), double(y1)}, axis);
  drawText(image, {(x0 + x1) / 2 - 60, y1 + 38}, panel.xLabel, axis, 13);
  drawText(image, {left + 8, y0 - 10}, panel.yLabel, axis, 13);
  int legend = y0 + 14;
  for (const PlotSeries& s : panel.series) {
    std::vector<glm::dvec2> pixels;
    for (const glm::dvec2& p : s.points)
      if (std::isfinite(p.x) && std::isfinite(p.y)) {
        pixels.push_back(toPixel(glm::dvec2(p.x, std::min(p.y, high.y))));
        if (p.y > high.y) markClipped(image, pixels.back(), s.colour);
      }
    if (s.line) {
      for (size_t i = 1; i < pixels.size(); ++i) drawLine(image, pixels[i - 1], pixels[i], s.colour);
    } else {
      for (const glm::dvec2& p : pixels)
        fillConvexPolygon(image, std::vector<glm::dvec2>{p + glm::dvec2(-3, -3), p + glm::dvec2(3, -3), p + glm::dvec2(3, 3), p + glm::dvec2(-3, 3)},
                          s.colour, 1.0f);
    }
    if (!s.label.empty()) {
      drawText(image, {x1 - 150, legend}, s.label, s.colour, 13);
      legend += 16;
    }
  }
  if (yRange.clipped)
    drawText(image, {x0 + 8, y1 - 8}, fmt::format("{} clipped at the top (peak {:.3g})", yRange.clipped->label, yRange.clippedPeak),
             yRange.clipped->colour, 12);
}

}  // namespace

PlotYRange plotYRange(const PlotPanel& panel) {
  constexpr double kNone = -std::numeric_limits<double>::infinity();
  PlotYRange range;
  double lowest = 0.0, highest = kNone;
  for (const PlotSeries& s : panel.series) {
    for (const glm::dvec2& p : s.points)
      if (std::isfinite(p.x) && std::isfinite(p.y)) lowest = std::min(lowest, p.y);
    highest = std::max(highest, peakOf(s));
  }
  range.low = lowest;
  range.high = std::isfinite(highest) ? highest : lowest + 1.0;
  // The series with the highest level, the next level, and the other series' highest peak.
  const PlotSeries* top = nullptr;
  double topLevel = kNone, nextLevel = kNone;
  for (const PlotSeries& s : panel.series) {
    const double level = levelOf(s);
    if (level > topLevel) {
      nextLevel = topLevel;
      topLevel = level;
      top = &s;
    } else {
      nextLevel = std::max(nextLevel, level);
    }
  }
  if (top && std::isfinite(nextLevel) && nextLevel > lowest && topLevel - lowest > kPlotClipRatio * (nextLevel - lowest)) {
    double othersPeak = kNone;
    for (const PlotSeries& s : panel.series)
      if (&s != top) othersPeak = std::max(othersPeak, peakOf(s));
    range.high = lowest + kPlotClipHeadroom * (othersPeak - lowest);
    range.clipped = top;
    range.clippedPeak = peakOf(*top);
  }
  if (!(range.high > range.low)) range.high = range.low + 1.0;
  range.high += 0.05 * (range.high - range.low);
  return range;
}

Image8 plotPanels(const std::vector<PlotPanel>& panels, int columns, int panelWidth, int panelHeight) {
  columns = std::max(1, columns);
  const int rows = std::max(1, static_cast<int>((panels.size() + columns - 1) / columns));
  Image8 image(columns * panelWidth, rows * panelHeight, 3);
  std::fill(image.pixels.begin(), image.pixels.end(), std::uint8_t{255});
  for (size_t i = 0; i < panels.size(); ++i)
    drawPanel(image, panels[i], static_cast<int>(i % columns) * panelWidth, static_cast<int>(i / columns) * panelHeight,
              panelWidth, panelHeight);
  return image;
}

std::vector<glm::dvec2> paretoFront(std::vector<glm::dvec2> points) {
  std::erase_if(points, [](const glm::dvec2& p) { return !std::isfinite(p.x) || !std::isfinite(p.y); });
  std::sort(points.begin(), points.end(), [](const glm::dvec2& a, const glm::dvec2& b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
  std::vector<glm::dvec2> front;
  for (const glm::dvec2& p : points)
    if (front.empty() || p.y < front.back().y) front.push_back(p);
  return front;
}

}  // namespace forest
