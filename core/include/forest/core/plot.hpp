#pragma once
// Scatter and line plots as RGB images (for reports a person looks at next to the JSON): panels in
// a grid, each with axes, tick values, a title and a legend. Drawn with drawing.hpp.
#include <glm/glm.hpp>

#include <string>
#include <vector>

#include "forest/core/image.hpp"

namespace forest {

struct PlotSeries {
  std::string label;  // empty: not in the legend
  glm::vec3 colour{0.0f};
  std::vector<glm::dvec2> points;
  bool line = false;  // join the points in order (e.g. a Pareto front) instead of marking them
};

struct PlotPanel {
  std::string title, xLabel, yLabel;
  std::vector<PlotSeries> series;
};

// The y range a panel shows: from 0 (or the lowest value) to the highest plus 5%. One series far
// above the rest would flatten every other line, so where the highest series' level (its median,
// the upper one of an even count; from the lowest value) is more than kPlotClipRatio times the next
// highest level, the range ends at kPlotClipHeadroom times the other series' highest peak instead:
// the points above are drawn at the top edge, marked by an arrow, and the panel says which series
// was clipped and its peak. A spike of one series (a first frame) clips nothing.
constexpr double kPlotClipRatio = 4.0;
constexpr double kPlotClipHeadroom = 1.5;
struct PlotYRange {
  double low = 0.0, high = 1.0;
  const PlotSeries* clipped = nullptr;  // the series cut at the top edge, if any
  double clippedPeak = 0.0;
};
PlotYRange plotYRange(const PlotPanel& panel);

// The panels left to right, top to bottom, `columns` per row. Non-finite points are skipped.
Image8 plotPanels(const std::vector<PlotPanel>& panels, int columns, int panelWidth = 520, int panelHeight = 380);

// The points of `points` no other point beats in both coordinates (smaller is better in x and y),
// sorted by x: the Pareto front.
std::vector<glm::dvec2> paretoFront(std::vector<glm::dvec2> points);

}  // namespace forest
