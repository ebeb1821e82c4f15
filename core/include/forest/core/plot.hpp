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

// The panels left to right, top to bottom, `columns` per row. Non-finite points are skipped.
Image8 plotPanels(const std::vector<PlotPanel>& panels, int columns, int panelWidth = 520, int panelHeight = 380);

// The points of `points` no other point beats in both coordinates (smaller is better in x and y),
// sorted by x: the Pareto front.
std::vector<glm::dvec2> paretoFront(std::vector<glm::dvec2> points);

}  // namespace forest
