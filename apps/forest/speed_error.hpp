#pragma once
// forest bench speed-error (command_speed_error.cpp runs the sweep, speed_error_report.cpp writes
// what it found): the sweep's options, scenarios and rows.
#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <vector>

#include "commands.hpp"
#include "forest/core/scene.hpp"
#include "forest/shadows/shadow_setup.hpp"
#include "forest/truth/frame_truth.hpp"

namespace forest::app {

struct SpeedErrorOptions {
  GlOptions gl;
  std::string scene;
  std::string out = "out/speed-error";
  bool quick = false;
  ImageSizeOptions size{1280, 720};
  std::vector<int> sizes{512, 1024, 2048, 4096};
  // Slices per layout. K > 1 is swept at equal total texels: K layers of (size / √K)² for each size
  // (4 × 1024² against 1 × 2048²), focus on the receivers only; layers under 512² are left out.
  std::vector<int> cascades{1, 4};
  // Unequal layers: with K > 1 the last layer's side is this many times the others' (still at equal
  // total texels: (K − 1 + scale²) · layer² = size²). 1: equal layers.
  double farSliceScale = 1.0;
  double target = 0.02;  // misclassification for the equal-error map sizes
  int softRays = 8;      // fewer than truth's 16: the sweep scores 130 frames
  std::string termResolution = FrameOptions{}.termResolution;  // of the blurred term: full or half
  ModeOptions modes;
  CasterOptions casters;
  bool quiet = false;
};

// The methods compared (shadows::comparedShadowMethods), by name.
inline const std::vector<std::string> kSpeedErrorMethods = [] {
  std::vector<std::string> names;
  for (shadows::ShadowMethod method : shadows::comparedShadowMethods()) names.emplace_back(shadows::kShadowMethodNames.name(method));
  return names;
}();
inline const std::vector<std::string> kSpeedErrorFocus{"receivers", "frustum"};

struct Scenario {
  std::string name;
  Camera camera;
  glm::dvec3 sun;  // the way light travels
};

// A map layout: K slices of layerSize², as many texels as one totalSide² map.
struct MapLayout {
  int cascades = 1;
  int layerSize = 0;
  int totalSide = 0;
  double farScale = 1.0;  // K > 1: the last layer's side over layerSize (FrameSettings::farSliceScale)
  int farSize() const;    // the last layer's side
  long long texels() const;
  std::string label() const;  // "2048²", "4×1024²" or "3×894²+1341²"
};
// The sweep's layouts: each K of `cascades` at each total size of `sizes`, with K > 1 the last
// layer `farScale` times the others' side at the same total texels.
std::vector<MapLayout> mapLayouts(const std::vector<int>& sizes, const std::vector<int>& cascades, double farScale = 1.0);

struct Row {
  std::string scenario, method, focus;
  MapLayout layout;
  bool blur = false;
  double frameMs = 0.0, shadowMs = 0.0;
  long long shadowTriangles = 0;
  truth::FrameError error;
  double softError = 0.0;  // of the term lighting used (blurred or not)
};

// The flicker walk again with the trees swaying (30 frames a second) and kept slices: redrawn every
// frame, cached (--cache-slices on) and staggered (--cache-slices staggered); the last view of each
// scored against the truth at the same time — what a cached layer's sway of up to a texel, or a
// staggered layer's stale casters, cost — with the shadow triangles drawn over the walk and what
// the layers did.
struct WalkPass {
  truth::FrameError lastView;
  long long triangles = 0;          // shadow triangles over the walk
  int reused = 0, added = 0, redrawn = 0;  // layers over the walk
};
struct CachedWalk {
  bool measured = false;
  WalkPass redrawn, cached, staggered;
};

struct FlickerRow {
  std::string method, focus;
  MapLayout layout;
  bool keep = false;     // kept slices (FrameSettings::keepSlices)
  truth::FlickerResult result;
  double frameMs = 0.0;  // the first scenario's frame with this method and layout
  // The walk's last view, rendered once more after the walk and scored against the truth: what a
  // kept map's margin costs in misclassified pixels (and by distance band).
  truth::FrameError lastView;
  long long lastViewShadowTriangles = 0;
  CachedWalk cached;  // rows with kept slices
};

// "uniform" or "uniform ×4": a series of the plots and tables.
std::string seriesName(const std::string& method, int cascades);

// Writes report.json, results.csv, table.md, the plots and worst-case images into `out`; returns
// table.md's text.
std::string writeSpeedErrorReport(const std::filesystem::path& out, const SpeedErrorOptions& options, const std::string& scenePath,
                                  const std::string& device, const nlohmann::ordered_json& modes, int width, int height,
                                  const std::vector<Scenario>& scenarios, const std::vector<MapLayout>& layouts,
                                  const std::vector<Row>& rows, const std::vector<FlickerRow>& flicker);

}  // namespace forest::app
