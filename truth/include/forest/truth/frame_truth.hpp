#pragma once
// A rendered frame against the ray-traced truth of the same geometry (DESIGN §5): the Embree
// mirror of everything drawn (terrain at the frame's LOD and morph, trees at their LOD and sway,
// props), primary rays to find the pixels the truth and the G-buffer agree on, shadow rays from
// them, and the error figures of the frame.
#include <cstdint>
#include <span>
#include <vector>

#include "forest/core/camera.hpp"
#include "forest/core/image.hpp"
#include "forest/core/scene.hpp"
#include "forest/render/frame.hpp"
#include "forest/shadows/aliasing.hpp"

namespace forest::truth {

struct TruthOptions {
  int softRays = 16;            // rays over the sun's disc for the soft truth (0: none)
  double sunDiscDeg = 0.53;     // the sun's angular diameter
  int edgePixels = 3;           // "near an edge": within this many pixels of a true shadow edge
  // The shadow ray starts kOffsetUlps float32 ulps of |p| along the geometric normal (the mirror
  // traces in float32).
  double offsetUlps = 256.0;
  // Edges (metres from the eye, increasing) of the distance bands the misclassification is also
  // split into: [0, 50), [50, 200), [200, ∞) by default — near field, mid field, far field
  // (issue "Z-partitioned shadows").
  std::vector<double> bandEdges{50.0, 200.0};
};

// The lit-facing pixels whose ray-traced hit lies [fromM, toM) from the eye, and the share of them
// misclassified.
struct DistanceBand {
  double fromM = 0.0, toM = 0.0;  // toM = +∞ for the last band
  int litFacing = 0;
  int misclassified = 0;
  double misclassification = 0.0;  // misclassified / litFacing (0 when empty)
};

struct CasterOracle {
  int selected = 0;                  // culling objects the frame selected as casters
  int needed = 0;                    // culling objects that occlude the sun for a scored pixel
  // Needed but not drawn: 0, except where a selection culls the casters hidden from the sun by
  // others (CasterSelection::ReceiverMaskGpu, ReceiverPixels with FrameSettings::cullHiddenCasters:
  // they keep the crown nearer the sun of two a ray meets, the oracle names the one nearer the pixel).
  int missing = 0;
  long long selectedTriangles = 0;   // drawn in the shadow pass
  long long neededTriangles = 0;     // of the occluding instances (trees, tiles, props)
  std::vector<std::uint32_t> missingObjects;
};

struct FrameError {
  int pixels = 0;              // width × height
  int scored = 0;              // truth and G-buffer see the same object (not sky)
  int litFacing = 0;           // scored, geometric normal towards the sun
  int nearEdge = 0;            // lit-facing, within edgePixels of a true edge
  // Shares of the lit-facing pixels where the term the lighting used (after the blur and, at half
  // resolution, the upsample; threshold 0.5) disagrees with the truth.
  double misclassification = 0.0;
  double misclassificationNearEdge = 0.0;   // of the near-edge pixels
  double misclassificationElsewhere = 0.0;  // of the others
  std::vector<DistanceBand> bands;           // TruthOptions::bandEdges' bands, nearest first
  double falseShadow = 0.0;    // rendered shadow, truth lit
  double falseLight = 0.0;     // rendered lit, truth shadowed
  double softMeanAbsoluteError = 0.0;  // blurred term against the sun-disc truth (softRays > 0)
  double softMeanAbsoluteErrorUnblurred = 0.0;  // the term before the blur against the same truth
  shadows::ErrorStatistics aliasingPixels;     // per pixel, with its normal: pixels per texel
  shadows::ErrorStatistics aliasingRelative;   // per pixel, perspective part (eq. 8.1), relative units
  CasterOracle casters;
  Image8 errorImage;           // RGB, top row first: false shadow red, false light blue, agreement grey
  // Per pixel, rows bottom-up as GL stores them: −1 not scored or not lit-facing, 0 the truth is
  // shadowed, 1 lit.
  std::vector<std::int8_t> truthState;
};

// Evaluates the frame just rendered by `frame` (returning `stats`) for `camera` at `time`, of the
// scene the frame was built from. Needs the frame's GL context current (reads its buffers back).
FrameError evaluateFrame(const render::Frame& frame, const render::FrameStats& stats, const Scene& scene,
                         const Camera& camera, double time, const TruthOptions& options = {});

struct FlickerResult {
  int probes = 0;        // world points on visible lit-facing receivers of the first frame
  int comparisons = 0;   // probe states compared between consecutive frames (probe in both maps)
  int changes = 0;       // of those, how many changed
  int slices = 0;        // slices drawn over the walk's frames after the first
  int slicesKept = 0;    // of those, how many kept their map (FrameSettings::keepSlices)
  double share() const { return comparisons ? static_cast<double>(changes) / comparisons : 0.0; }
};

// Flicker (TSM §5; DESIGN §5): the scene and sun fixed (`time`), the camera moving along
// `cameras`; each frame's shadow map is looked up at fixed probe points (2×2 PCF as the hardware
// filters it, threshold 0.5) and every change of a probe's state counts.
FlickerResult measureFlicker(render::Frame& frame, const Scene& scene, std::span<const Camera> cameras, double time,
                             const render::FrameSettings& settings, int probeSpacingPixels = 8);

}  // namespace forest::truth
