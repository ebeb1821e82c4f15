// Which cells of a terrain block inside a morph ramp may write into a backside shadow map (DESIGN
// §4): its triangles, tested one by one at the morph factors the frame's LOD gives their vertices;
// the runs of cells with a triangle that may face away (the shadow pass draws their index ranges
// only: a ramp block is mostly kept for a few slivers).
//
// A triangle (p0, p1, p2) is turned toward the sun when f = ((p1 − p0) × (p2 − p0))·s ≥ 0 with
// s = toSun − m·toSun_y·ŷ (m = BlockFacing::kFacingMargin, the margin the unmorphed and morphed
// blocks keep too). The GPU's vertices differ from the CPU twin's (Terrain::drawnVertex) by float
// rounding, and by the rounding of each vertex's morph factor k times the length of its slide; if
// each vertex lies within ε of the twin's, every edge is within 2ε of its own, so
//   |Δf| ≤ |s| (2ε |e1| + 2ε |e2| + 4ε²)   (e1 = p1 − p0, e2 = p2 − p0)
// and f > |Δf| on the twin's triangle means the GPU's is turned toward the sun as well.
// ε, with u = 2⁻²⁴ (GLSL: +, −, × correctly rounded, ÷ within 2.5 ulps) and every term doubled
// for contractions into FMAs and the like:
//   the sample's camera-relative position, origin + s·spacing and h − eye_y: 4u·M, M the
//     magnitudes involved (the terrain's size, the eye's offset from it, its height range);
//   the distance |fine − eye| and the ramp parameter t = (d − start)/width: Δt ≤ (ε_sample +
//     4u(d + end))/width + 4u; k = t(1 + 2σ) − σ, clamped: Δk ≤ (1 + 2σ)Δt + 2u;
//   the mix fine(1 − k) + target·k: 3u(d + slide) plus Δk·slide;
//   the projection into the map: 8u·d (its relative errors are the facing margin's).
// Where the clamp holds for every t within Δt, k is exactly 0 or 1 and the vertex lies exactly
// on its sample (terrain.vert: a·(1 − k) + b·k is exactly b at k = 1).
// A triangle collapsed exactly on the GPU (two vertices on the same sample, each with k exactly 0
// or 1 there) has no fragments and is skipped; one collapsed only nearly counts as facing away.
#include <glm/glm.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "forest/terrain/terrain.hpp"

namespace forest::terrain {
namespace {

using glm::dvec3;

constexpr double kUlp = 0x1p-24;  // u: float32's unit roundoff

struct RampVertex {
  dvec3 position;   // the CPU twin's
  double error;     // the GPU's lies within this distance of it (metres)
  int exactSample;  // the local sample the GPU's lies on exactly (i + 65 j), or −1
};

}  // namespace

void Terrain::rampCellsThatMayFaceAway(int tile, int level, int block, const TerrainLod& lod, const dvec3& toSun,
                                       std::vector<CellSpan>& runs) const {
  const Heightfield& h = heightfield_;
  const int step = 1 << level, quads = blockQuads(level), perSide = kTileQuads / quads;
  const int i0 = (block % perSide) * quads, j0 = (block / perSide) * quads, n = quads / step + 1;
  const double start = lod.morphStart[static_cast<size_t>(level)], width = lod.morphEnd[static_cast<size_t>(level)] - start;
  const double slack = TerrainLod::kMorphSlack;
  // M: the magnitudes samplePosition rounds against (the terrain's origin and size, the eye's
  // offset from the terrain, heights).
  const double magnitudes = h.size() + glm::length(lod.eye - bounds_.centre()) + (bounds_.max.y - bounds_.min.y);
  const double sampleError = 2.0 * 4.0 * kUlp * magnitudes;
  const double end = lod.morphEnd[static_cast<size_t>(level)];
  thread_local std::vector<RampVertex> vertices;  // kept from call to call: no allocation per block
  vertices.resize(static_cast<size_t>(n * n));
  for (int b = 0; b < n; ++b)
    for (int a = 0; a < n; ++a) {
      const int i = i0 + a * step, j = j0 + b * step;
      const int ti = (i / step) % 2 == 1 ? i - step : i, tj = (j / step) % 2 == 1 ? j - step : j;  // the target's sample
      const auto [fine, target] = morphEnds(tile, i, j, level);
      const double distance = glm::distance(fine, lod.eye), slide = glm::distance(fine, target);
      const double t = (distance - start) / width;
      const double tError = 2.0 * ((sampleError + 4.0 * kUlp * (distance + end)) / width + 4.0 * kUlp);
      const double k = lod.morphFactor(level, distance);
      int exactSample = -1;
      if ((t + tError) * (1.0 + 2.0 * slack) - slack <= 0.0) exactSample = i + 65 * j;
      if ((t - tError) * (1.0 + 2.0 * slack) - slack >= 1.0) exactSample = ti + 65 * tj;
      const double kError = exactSample >= 0 ? 0.0 : (1.0 + 2.0 * slack) * tError + 2.0 * 2.0 * kUlp;
      const double error = sampleError + 2.0 * 3.0 * kUlp * (distance + slide) + kError * slide + 2.0 * 8.0 * kUlp * distance;
      vertices[static_cast<size_t>(b * n + a)] = {fine * (1.0 - k) + target * k, error, exactSample};
    }

  const dvec3 s = toSun - BlockFacing::kFacingMargin * toSun.y * dvec3(0.0, 1.0, 0.0);
  const double sLength = glm::length(s);
  // (00, 01, 11) and (00, 11, 10) per cell, as tileGridIndices winds them.
  auto facesAway = [&](const RampVertex& v0, const RampVertex& v1, const RampVertex& v2) {
    const int e0 = v0.exactSample, e1 = v1.exactSample, e2 = v2.exactSample;
    if ((e0 >= 0 && (e0 == e1 || e0 == e2)) || (e1 >= 0 && e1 == e2)) return false;  // no fragments
    const dvec3 edge1 = v1.position - v0.position, edge2 = v2.position - v0.position;
    const double error = std::max({v0.error, v1.error, v2.error});
    const double deviation = sLength * (2.0 * error * (glm::length(edge1) + glm::length(edge2)) + 4.0 * error * error);
    return !(glm::dot(glm::cross(edge1, edge2), s) > deviation);
  };
  // Cell (a, b) is cell b · (n − 1) + a of blockGridIndices; a run continues over a row's end.
  const size_t before = runs.size();
  for (int b = 0; b + 1 < n; ++b)
    for (int a = 0; a + 1 < n; ++a) {
      const RampVertex &v00 = vertices[static_cast<size_t>(b * n + a)], &v10 = vertices[static_cast<size_t>(b * n + a + 1)];
      const RampVertex &v01 = vertices[static_cast<size_t>((b + 1) * n + a)], &v11 = vertices[static_cast<size_t>((b + 1) * n + a + 1)];
      if (!facesAway(v00, v01, v11) && !facesAway(v00, v11, v10)) continue;
      const int cell = b * (n - 1) + a;
      if (runs.size() > before && runs.back().end == cell)
        runs.back().end = cell + 1;
      else
        runs.push_back({cell, cell + 1});
    }
}

}  // namespace forest::terrain
