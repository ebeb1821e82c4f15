#include "forest/truth/frame_truth.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <set>

#include "forest/core/error.hpp"
#include "forest/core/parallel.hpp"
#include "forest/raytrace/scene_mirror.hpp"

namespace forest::truth {
namespace {

using glm::dvec3;
using raytrace::kNoObject;

constexpr double kFloatUlp = 0x1p-23;  // float32 spacing relative to the magnitude

// What the truth sees through one pixel.
struct PixelTruth {
  bool scored = false;      // the truth hits the object the G-buffer shows
  bool litFacing = false;   // its geometric normal faces the sun
  bool shadowed = false;    // the shadow ray towards the sun's centre hits something
  float soft = 1.0f;        // share of the sun's disc visible
  std::uint32_t occluder = kNoObject;  // the object the shadow ray hit first
  dvec3 position{0.0}, normal{0.0};
};

// The mirror of what `frame` drew for `camera` at `time`.
void buildMirror(raytrace::RayScene& rays, const render::Frame& frame, const Scene& scene, const Camera& camera,
                 double time) {
  std::optional<terrain::TerrainLod> lod;
  if (frame.terrain()) lod = frame.terrain()->lodFor(camera, frame.height());
  const render::SceneObjects& objects = frame.objects();
  raytrace::MirrorOptions options;
  options.terrainIdBase = objects.terrainIdBase();
  options.treeIdBase = objects.treeIdBase();
  options.propIdBase = objects.propIdBase();
  options.time = time;
  options.props = &scene.props;
  raytrace::mirrorScene(rays, frame.terrain(), lod ? &*lod : nullptr, frame.forest(), camera, options);
}

// Traces pixel (x, y) (rows bottom-up, as GL stores them) against the G-buffer's object ID.
PixelTruth tracePixel(const raytrace::RayScene& rays, const Camera& camera, const glm::dmat4& inverseViewProjection,
                      int x, int y, int width, int height, std::uint32_t gbufferId, const dvec3& toSun,
                      const TruthOptions& options, bool soft) {
  PixelTruth t;
  if (gbufferId == 0) return t;  // sky
  const glm::dvec4 h = inverseViewProjection * glm::dvec4(2.0 * (x + 0.5) / width - 1.0, 2.0 * (y + 0.5) / height - 1.0, 0.5, 1.0);
  const dvec3 direction = glm::normalize(dvec3(h) / h.w - camera.position);
  const double cosine = glm::dot(direction, camera.forward());
  const raytrace::RayHit hit = rays.intersect(camera.position, direction, camera.near / cosine, camera.far / cosine);
  if (!hit.hit || hit.objectId != gbufferId) return t;
  t.scored = true;
  t.position = camera.position + hit.distance * direction;
  t.normal = glm::dot(hit.normal, direction) > 0.0 ? -hit.normal : hit.normal;  // the side the eye sees
  t.litFacing = glm::dot(t.normal, toSun) > 0.0;
  if (!t.litFacing) return t;
  // Offset along the geometric normal by float32 ulps of |p| (the mirror traces in float32).
  const double epsilon = options.offsetUlps * kFloatUlp * std::max(1.0, glm::length(t.position));
  const dvec3 origin = t.position + epsilon * t.normal;
  const raytrace::RayHit shadow = rays.intersect(origin, toSun);
  t.shadowed = shadow.hit;
  t.occluder = shadow.hit ? shadow.objectId : kNoObject;
  if (soft && options.softRays > 0) {
    // Rays spread over the sun's disc on a golden-angle spiral (equal area per ray).
    const dvec3 helper = std::abs(toSun.y) < 0.9 ? dvec3(0, 1, 0) : dvec3(1, 0, 0);
    const dvec3 u = glm::normalize(glm::cross(toSun, helper)), v = glm::cross(toSun, u);
    const double radius = std::tan(glm::radians(0.5 * options.sunDiscDeg));
    int visible = 0;
    for (int k = 0; k < options.softRays; ++k) {
      const double r = radius * std::sqrt((k + 0.5) / options.softRays), angle = 2.399963229728653 * k;
      const dvec3 d = glm::normalize(toSun + r * (std::cos(angle) * u + std::sin(angle) * v));
      visible += rays.occluded(origin, d) ? 0 : 1;
    }
    t.soft = static_cast<float>(visible) / static_cast<float>(options.softRays);
  }
  return t;
}

// The distance bands of options.bandEdges, empty.
std::vector<DistanceBand> distanceBands(const TruthOptions& options) {
  std::vector<DistanceBand> bands;
  for (size_t k = 0; k <= options.bandEdges.size(); ++k) {
    DistanceBand band;
    band.fromM = k == 0 ? 0.0 : options.bandEdges[k - 1];
    band.toM = k < options.bandEdges.size() ? options.bandEdges[k] : std::numeric_limits<double>::infinity();
    if (!(band.toM > band.fromM)) throw InputError("truth: the distance bands' edges must increase");
    bands.push_back(band);
  }
  return bands;
}

// Near a true edge: a lit-facing pixel within `reach` pixels whose truth is the other.
bool nearTrueEdge(const std::vector<PixelTruth>& truth, int x, int y, int width, int height, int reach) {
  const PixelTruth& t = truth[static_cast<size_t>(y) * width + x];
  for (int dy = -reach; dy <= reach; ++dy)
    for (int dx = -reach; dx <= reach; ++dx) {
      const int nx = x + dx, ny = y + dy;
      if (nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
      const PixelTruth& o = truth[static_cast<size_t>(ny) * width + nx];
      if (o.litFacing && o.shadowed != t.shadowed) return true;
    }
  return false;
}

// What scoring the pixels counts, before the shares.
struct Tallies {
  int wrong = 0, wrongNear = 0, falseShadow = 0, falseLight = 0;
  double softError = 0.0, softErrorUnblurred = 0.0;
  std::vector<double> aliasingPixels, aliasingRelative;
};

// Each scored pixel's rendered term against its truth: the counts, the error image (sky white,
// unscored dark, false shadow red, false light blue, agreement grey by state), the bands, the
// soft error and the aliasing of the slice the pixel reads.
void scorePixels(const render::Frame& frame, const std::vector<PixelTruth>& truth, const std::vector<std::uint32_t>& ids,
                 const std::vector<float>& term, const std::vector<float>& blurred, const Camera& camera, const dvec3& l,
                 const TruthOptions& options, FrameError& e, Tallies& n) {
  const int width = frame.width(), height = frame.height();
  const dvec3 forward = camera.forward();
  const auto bandOf = [&](const dvec3& p) -> DistanceBand& {
    const double distance = glm::distance(p, camera.position);
    size_t k = 0;
    while (k + 1 < e.bands.size() && distance >= e.bands[k].toM) ++k;
    return e.bands[k];
  };
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const size_t i = static_cast<size_t>(y) * width + x;
      const PixelTruth& t = truth[i];
      std::uint8_t* out = &e.errorImage.at(x, height - 1 - y);
      out[0] = out[1] = out[2] = ids[i] == 0 ? 255 : 40;  // sky white, unscored dark
      if (!t.scored) continue;
      ++e.scored;
      if (!t.litFacing) continue;
      ++e.litFacing;
      e.truthState[i] = t.shadowed ? 0 : 1;
      DistanceBand& band = bandOf(t.position);
      ++band.litFacing;
      const bool nearEdge = nearTrueEdge(truth, x, y, width, height, options.edgePixels);
      e.nearEdge += nearEdge ? 1 : 0;
      const bool renderedShadow = blurred[i] < 0.5f;  // what the image shows
      if (renderedShadow != t.shadowed) {
        ++n.wrong;
        ++band.misclassified;
        n.wrongNear += nearEdge ? 1 : 0;
        (renderedShadow ? n.falseShadow : n.falseLight) += 1;
        out[0] = renderedShadow ? 230 : 30;
        out[1] = 30;
        out[2] = renderedShadow ? 30 : 230;
      } else {
        out[0] = out[1] = out[2] = t.shadowed ? 110 : 190;
      }
      n.softError += std::abs(static_cast<double>(blurred[i]) - t.soft);
      n.softErrorUnblurred += std::abs(static_cast<double>(term[i]) - t.soft);
      // The slice whose layer the pixel reads, by its eye depth (in a blend band, the farther one).
      const int slice = frame.cascadeOf(glm::dot(t.position - camera.position, forward));
      const shadows::ShadowSetup& setup = frame.shadowSetup(slice);
      if (!setup.empty) {
        const auto a = shadows::surfaceAliasing(setup, camera, t.position, t.normal, l, frame.shadowMapSize(slice), width, height);
        if (a && std::isfinite(a->footprint)) n.aliasingPixels.push_back(a->footprint);
        const double r = shadows::perspectiveAliasing(setup, camera, t.position);
        if (std::isfinite(r)) n.aliasingRelative.push_back(r);
      }
    }
  }
}

// The caster oracle, in culling objects (each tree is one): the first occluder of each lit-facing
// pixel's shadow ray, against the casters any slice's layer drew.
CasterOracle casterOracle(const render::Frame& frame, const render::FrameStats& stats, const raytrace::RayScene& rays,
                         const std::vector<PixelTruth>& truth) {
  CasterOracle c;
  std::set<std::uint32_t> occluderIds;
  for (const PixelTruth& t : truth)
    if (t.litFacing && t.occluder != kNoObject) occluderIds.insert(t.occluder);
  std::set<std::int64_t> needed;
  for (std::uint32_t id : occluderIds) {
    c.neededTriangles += static_cast<long long>(rays.triangles(id));
    needed.insert(frame.objects().objectOfId(id));
  }
  std::set<std::uint32_t> selected;  // in any slice's layer
  for (int slice = 0; slice < frame.cascadeCount(); ++slice) {
    const std::vector<std::uint32_t> casters = frame.casters(slice);  // drawn into its layer
    selected.insert(casters.begin(), casters.end());
  }
  c.selected = static_cast<int>(selected.size());
  c.selectedTriangles = stats.shadowTriangles;
  for (std::int64_t object : needed) {
    if (object < 0) continue;
    ++c.needed;
    if (!selected.contains(static_cast<std::uint32_t>(object))) c.missingObjects.push_back(static_cast<std::uint32_t>(object));
  }
  c.missing = static_cast<int>(c.missingObjects.size());
  return c;
}

}  // namespace

FrameError evaluateFrame(const render::Frame& frame, const render::FrameStats& stats, const Scene& scene,
                         const Camera& camera, double time, const TruthOptions& options) {
  const int width = frame.width(), height = frame.height();
  raytrace::RayScene rays;
  buildMirror(rays, frame, scene, camera, time);
  const std::vector<std::uint32_t> ids = frame.readObjectIds();
  const std::vector<float> term = frame.readShadowTerm(), blurred = frame.readBlurredShadowTerm();
  const dvec3 l = glm::normalize(scene.sun.direction), toSun = -l;
  const glm::dmat4 inverse = glm::inverse(camera.projection() * camera.view());
  const bool sunUp = l.y < 0.0;

  std::vector<PixelTruth> truth(static_cast<size_t>(width) * height);
  parallelFor(height, [&](int y) {
    for (int x = 0; x < width; ++x) {
      const size_t i = static_cast<size_t>(y) * width + x;
      truth[i] = tracePixel(rays, camera, inverse, x, y, width, height, ids[i], toSun, options, true);
      if (!sunUp) truth[i].litFacing = false;  // no sun: nothing to score
    }
  });

  FrameError e;
  e.pixels = width * height;
  e.errorImage = Image8(width, height, 3);
  e.truthState.assign(truth.size(), -1);
  e.bands = distanceBands(options);
  Tallies n;
  scorePixels(frame, truth, ids, term, blurred, camera, l, options, e, n);
  const double lit = std::max(1, e.litFacing);
  e.misclassification = n.wrong / lit;
  e.misclassificationNearEdge = e.nearEdge ? static_cast<double>(n.wrongNear) / e.nearEdge : 0.0;
  e.misclassificationElsewhere =
      e.litFacing > e.nearEdge ? static_cast<double>(n.wrong - n.wrongNear) / (e.litFacing - e.nearEdge) : 0.0;
  for (DistanceBand& band : e.bands)
    band.misclassification = band.litFacing > 0 ? static_cast<double>(band.misclassified) / band.litFacing : 0.0;
  e.falseShadow = n.falseShadow / lit;
  e.falseLight = n.falseLight / lit;
  e.softMeanAbsoluteError = options.softRays > 0 ? n.softError / lit : 0.0;
  e.softMeanAbsoluteErrorUnblurred = options.softRays > 0 ? n.softErrorUnblurred / lit : 0.0;
  e.aliasingPixels = shadows::summarise(std::move(n.aliasingPixels));
  e.aliasingRelative = shadows::summarise(std::move(n.aliasingRelative));
  e.casters = casterOracle(frame, stats, rays, truth);
  return e;
}

FlickerResult measureFlicker(render::Frame& frame, const Scene& scene, std::span<const Camera> cameras, double time,
                             const render::FrameSettings& settings, int probeSpacingPixels) {
  FlickerResult result;
  if (cameras.empty()) return result;
  if (probeSpacingPixels < 1) throw InputError("flicker: probe spacing must be at least 1 pixel");
  const dvec3 toSun = -glm::normalize(scene.sun.direction);
  // Probes: lit-facing points the truth and the G-buffer agree on, on a pixel grid of the first frame.
  frame.render(cameras[0], time, settings);
  std::vector<dvec3> probes;
  {
    raytrace::RayScene rays;
    buildMirror(rays, frame, scene, cameras[0], time);
    const std::vector<std::uint32_t> ids = frame.readObjectIds();
    const glm::dmat4 inverse = glm::inverse(cameras[0].projection() * cameras[0].view());
    TruthOptions options;
    options.softRays = 0;
    for (int y = probeSpacingPixels / 2; y < frame.height(); y += probeSpacingPixels)
      for (int x = probeSpacingPixels / 2; x < frame.width(); x += probeSpacingPixels) {
        const PixelTruth t = tracePixel(rays, cameras[0], inverse, x, y, frame.width(), frame.height(),
                                        ids[static_cast<size_t>(y) * frame.width() + x], toSun, options, false);
        if (t.litFacing) probes.push_back(t.position);
      }
  }
  result.probes = static_cast<int>(probes.size());
  // −1: not in the map; 0 shadowed; 1 lit.
  std::vector<int> previous(probes.size(), -1);
  for (size_t c = 0; c < cameras.size(); ++c) {
    if (c > 0) {
      const render::FrameStats stats = frame.render(cameras[c], time, settings);
      for (int slice = 0; slice < stats.cascades; ++slice) {
        ++result.slices;
        result.slicesKept += stats.cascade[static_cast<size_t>(slice)].keeping.kept ? 1 : 0;
      }
    }
    std::vector<std::vector<float>> maps;  // per slice
    for (int slice = 0; slice < frame.cascadeCount(); ++slice) maps.push_back(frame.readShadowMap(slice));
    for (size_t p = 0; p < probes.size(); ++p) {
      // The probe's slice in this frame, by its eye depth.
      const int slice = frame.cascadeOf(glm::dot(probes[p] - cameras[c].position, cameras[c].forward()));
      const int size = frame.shadowMapSize(slice);
      const shadows::ShadowSetup& setup = frame.shadowSetup(slice);
      const std::vector<float>& map = maps[static_cast<size_t>(slice)];
      auto stored = [&](int tx, int ty) {
        tx = std::clamp(tx, 0, size - 1);
        ty = std::clamp(ty, 0, size - 1);
        return map[static_cast<size_t>(ty) * size + tx];
      };
      const dvec3 m = setup.empty ? dvec3(2.0) : shadows::shadowMapCoordinates(setup, probes[p]);
      int state = -1;
      if (std::abs(m.x) <= 1.0 && std::abs(m.y) <= 1.0) {
        // GL_LINEAR with GL_COMPARE_REF_TO_TEXTURE: the 2×2 comparisons (ref ≤ stored: lit), weighted bilinearly.
        const double reference = 0.5 * m.z + 0.5;
        const double sx = (0.5 * m.x + 0.5) * size - 0.5, sy = (0.5 * m.y + 0.5) * size - 0.5;
        const int x0 = static_cast<int>(std::floor(sx)), y0 = static_cast<int>(std::floor(sy));
        const double fx = sx - x0, fy = sy - y0;
        auto lit = [&](int tx, int ty) { return reference <= stored(tx, ty) ? 1.0 : 0.0; };
        const double value = (1 - fx) * (1 - fy) * lit(x0, y0) + fx * (1 - fy) * lit(x0 + 1, y0) +
                             (1 - fx) * fy * lit(x0, y0 + 1) + fx * fy * lit(x0 + 1, y0 + 1);
        state = value >= 0.5 ? 1 : 0;
      }
      if (state >= 0 && previous[p] >= 0) {
        ++result.comparisons;
        result.changes += state != previous[p] ? 1 : 0;
      }
      previous[p] = state;
    }
  }
  return result;
}

}  // namespace forest::truth
