// Forest's placement (DESIGN §4 vegetation/): Poisson-disk dart throwing weighted by a density
// field, the site and the species' rules (Forest::place), or a jittered grid (Forest::placeOnGrid).
// A million trees: the darts' sites are computed in batches on all cores, the spacing test then
// runs in dart order on a flat grid, so the forest is the same on any number of cores.
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <optional>

#include "forest/core/log.hpp"
#include "forest/core/parallel.hpp"
#include "forest/core/random.hpp"
#include "forest/vegetation/forest.hpp"
#include "trail.hpp"

namespace forest::vegetation {
namespace {

using glm::dvec2;
using glm::dvec3;

const SpeciesPlacementSettings& placementOf(const VegetationSettings& s, Species species) {
  switch (species) {
    case Species::Conifer: return s.conifer;
    case Species::Broadleaf: return s.broadleaf;
    case Species::Shrub: return s.shrub;
  }
  return s.conifer;
}

// A species' weight at a site (scene.hpp, SpeciesPlacementSettings): share × one linear factor per
// bias, each factor in [0, 2] and 1 for a bias of 0. `altitude`, `slope` and `shade` are in [0, 1].
double siteWeight(const SpeciesPlacementSettings& rule, double altitude, double slope, double shade) {
  return rule.share * (1.0 + rule.altitude_bias * (2.0 * altitude - 1.0)) * (1.0 + rule.slope_bias * (2.0 * slope - 1.0)) *
         (1.0 + rule.shade_bias * (2.0 * shade - 1.0));
}

// A kept dart's site: terrain height (m), slope (degrees), altitude in the terrain's range [0, 1],
// the stand density there.
struct Site {
  double height, slope, altitude, density;
};

// The species at a site, by its weights among those whose height band and slope limit it passes
// (`draw` ∈ [0, 1) picks one); none when no species may grow there. inBand: some species' height
// band holds the site (the slope refused it).
std::optional<Species> speciesForSite(const VegetationSettings& settings, const Site& site, double draw, bool& inBand) {
  std::array<double, kSpeciesCount> weight{};
  for (Species s : kAllSpecies) {
    const SpeciesPlacementSettings& rule = placementOf(settings, s);
    if (!(rule.share > 0.0) || site.height < rule.min_height || site.height > rule.max_height) continue;
    inBand = true;
    if (site.slope > rule.max_slope_deg) continue;
    weight[static_cast<size_t>(s)] = siteWeight(rule, site.altitude, std::min(site.slope / 45.0, 1.0), site.density);
  }
  const double total = weight[0] + weight[1] + weight[2];
  if (!(total > 0.0)) return std::nullopt;
  for (double below = 0.0; Species s : kAllSpecies) {
    below += weight[static_cast<size_t>(s)];
    if (draw * total < below) return s;
  }
  return Species::Shrub;
}

// The size class for a uniform draw u in [0, 1), by the classes' normalised shares.
SizeClass sizeClassFor(const SizeClassSettings& sizes, double u) {
  const double total = sizes.share.x + sizes.share.y + sizes.share.z;
  const double x = u * total;
  return x < sizes.share.x ? SizeClass::Young : x < sizes.share.x + sizes.share.y ? SizeClass::Mature : SizeClass::Old;
}

// Darts per requested tree before placement gives up (the rest do not fit).
constexpr int kDartsPerTree = 30;

// Darts thrown per batch: their sites are independent of what is placed, so a batch is computed on
// all cores before its darts are tested against the placed trees one by one.
constexpr int kBatchDarts = 1 << 16;

// What a dart's site decides before the spacing test, with nothing placed yet.
enum class Verdict : std::uint8_t { Candidate, Field, Height, Slope, Trail };

struct Candidate {
  TreeInstance tree;
  double spacing = 0.0;  // its species' spacing × its size class's scale
  Verdict verdict = Verdict::Candidate;
};

// The trees placed so far, on square cells no smaller than the largest spacing, each cell's trees
// side by side in memory: the spacing test looks at the 3 × 3 cells around a dart, the dart's own
// first (where a tree that refuses it most often stands). A list threaded through one array of all
// the trees cost a cache miss per tree looked at: 13 M darts reach this test at a million trees.
class SpacingGrid {
 public:
  SpacingGrid(const dvec2& lo, const dvec2& hi, double cell)
      : lo_(lo), cell_(cell), cellsX_(std::max(1, static_cast<int>(std::ceil((hi.x - lo.x) / cell)))),
        cellsZ_(std::max(1, static_cast<int>(std::ceil((hi.y - lo.y) / cell)))), cells_(static_cast<size_t>(cellsX_) * cellsZ_) {}

  // No placed tree nearer than the larger of the two spacings.
  bool free(const dvec2& p, double spacing) const {
    const glm::ivec2 c = cellOf(p);
    const size_t own = index(c.x, c.y);
    return freeIn(own, p, spacing) && eachCellAround(c, [&](size_t cell) { return cell == own || freeIn(cell, p, spacing); });
  }
  void add(const dvec2& p, double spacing) {
    const glm::ivec2 c = cellOf(p);
    cells_[index(c.x, c.y)].push_back({p.x, p.y, spacing});
  }
  // The darts of a batch are known ahead, so free() on one overlaps the memory fetches for later
  // ones: first the 3 × 3 cells' headers around p, then (once those are in) their trees.
  void prefetchCells(const dvec2& p) const {
    eachCellAround(cellOf(p), [&](size_t cell) {
      __builtin_prefetch(&cells_[cell]);
      return true;
    });
  }
  void prefetchTrees(const dvec2& p) const {
    eachCellAround(cellOf(p), [&](size_t cell) {
      __builtin_prefetch(cells_[cell].data());
      return true;
    });
  }

 private:
  struct Placed {
    double x, z, spacing;
  };
  // visit(cell) for the 3 × 3 cells around cell c (fewer at the grid's edge) while it returns true;
  // whether it always did.
  template <typename Visit>
  bool eachCellAround(const glm::ivec2& c, const Visit& visit) const {
    for (int z = std::max(c.y - 1, 0); z <= std::min(c.y + 1, cellsZ_ - 1); ++z)
      for (int x = std::max(c.x - 1, 0); x <= std::min(c.x + 1, cellsX_ - 1); ++x)
        if (!visit(index(x, z))) return false;
    return true;
  }
  bool freeIn(size_t cell, const dvec2& p, double spacing) const {
    for (const Placed& o : cells_[cell]) {
      const double dx = o.x - p.x, dz = o.z - p.y;
      if (std::sqrt(dx * dx + dz * dz) < std::max(spacing, o.spacing)) return false;
    }
    return true;
  }
  glm::ivec2 cellOf(const dvec2& p) const {
    return {std::clamp(static_cast<int>((p.x - lo_.x) / cell_), 0, cellsX_ - 1), std::clamp(static_cast<int>((p.y - lo_.y) / cell_), 0, cellsZ_ - 1)};
  }
  size_t index(int x, int z) const { return static_cast<size_t>(z) * cellsX_ + x; }

  dvec2 lo_;
  double cell_;
  int cellsX_, cellsZ_;
  std::vector<std::vector<Placed>> cells_;
};

}  // namespace

TreeInstance Forest::varied(Species species, SizeClass size, const glm::dvec3& base, const double (&variation)[5]) const {
  TreeInstance tree;
  tree.species = species;
  tree.size = size;
  tree.position = base;
  tree.yaw = 2.0 * std::numbers::pi * variation[0];
  tree.scale = settings_.sizes.scale[static_cast<int>(size)] *
               (settings_.scale_range.x + (settings_.scale_range.y - settings_.scale_range.x) * variation[1]);
  // Young foliage is lighter, old darker.
  const float age = size == SizeClass::Young ? 1.1f : size == SizeClass::Old ? 0.92f : 1.0f;
  tree.tint = age * glm::vec3(static_cast<float>(0.9 + 0.2 * variation[2]), static_cast<float>(0.9 + 0.2 * variation[3]),
                              static_cast<float>(0.9 + 0.2 * variation[2] * variation[3]));
  tree.swayPhase = 2.0 * std::numbers::pi * variation[4];
  return tree;
}

void Forest::placeOnGrid() {
  // grid × grid cells over the placement area, one tree per cell, moved from the cell's centre
  // by up to ±40% of the cell in x and z (a jittered regular grid, thesis ch. 10).
  const auto [lo, hi] = placementArea();
  const dvec2 cell = (hi - lo) / static_cast<double>(settings_.grid);
  const double shares = settings_.conifer.share + settings_.broadleaf.share + settings_.shrub.share;
  SplitMix64 random(SplitMix64::substream(settings_.seed, 0x96edull));
  SplitMix64 sizeRandom(SplitMix64::substream(settings_.seed, 0x512eull));
  trees_.reserve(static_cast<size_t>(settings_.grid) * settings_.grid);
  for (int z = 0; z < settings_.grid; ++z)
    for (int x = 0; x < settings_.grid; ++x) {
      const double jitterZ = random.unit(), jitterX = random.unit();  // z first, as in place()
      const dvec2 p = lo + cell * dvec2(x + 0.5 + 0.8 * (jitterX - 0.5), z + 0.5 + 0.8 * (jitterZ - 0.5));
      const double u = random.unit() * shares;
      const Species species = u < settings_.conifer.share                              ? Species::Conifer
                              : u < settings_.conifer.share + settings_.broadleaf.share ? Species::Broadleaf
                                                                                         : Species::Shrub;
      const double variation[5] = {random.unit(), random.unit(), random.unit(), random.unit(), random.unit()};
      const SizeClass size = sizeClassFor(settings_.sizes, sizeRandom.unit());
      trees_.push_back(varied(species, size, {p.x, terrain_.heightAt(p.x, p.y), p.y}, variation));
    }
}

void Forest::place() {
  const auto [lo, hi] = placementArea();
  const double cell = std::max({settings_.conifer.spacing, settings_.broadleaf.spacing, settings_.shrub.spacing}) *
                      std::max({settings_.sizes.scale.x, settings_.sizes.scale.y, settings_.sizes.scale.z});
  SpacingGrid grid(lo, hi, cell);

  // With stands, a dart is kept with probability D (the density field), so more are thrown: about
  // 1 / mean(D) times as many.
  double keptShare = 1.0;
  if (settings_.stands) {
    stands_.emplace(*settings_.stands, settings_.seed, lo, hi);
    keptShare = stands_->standShare() + settings_.stands->meadow * (1.0 - stands_->standShare());
  }
  const Aabb ground = terrain_.bounds();
  const double altitudeRange = std::max(ground.max.y - ground.min.y, 1e-9);
  std::optional<TrailClearance> trail;
  if (settings_.trail) trail.emplace(*settings_.trail, species_, settings_.wind_strength, terrain_);

  // A dart's draws, in the order the streams give them (a dart takes the same draws whatever
  // becomes of it, so batches do not change the sequence).
  struct Draws {
    dvec2 p;
    double species, variation[5], size, keep;
  };
  // Everything but the spacing test: the density field, the height band and slope, the trail.
  const auto judge = [&](const Draws& d) {
    Candidate c;
    const double density = stands_ ? stands_->density(d.p.x, d.p.y) : 1.0;
    if (stands_ && d.keep >= density) {
      c.verdict = Verdict::Field;
      return c;
    }
    const double height = terrain_.heightAt(d.p.x, d.p.y);
    const double slope = glm::degrees(std::acos(std::clamp(terrain_.normalAt(d.p.x, d.p.y).y, -1.0, 1.0)));
    const double altitude = std::clamp((height - ground.min.y) / altitudeRange, 0.0, 1.0);
    bool inBand = false;
    const std::optional<Species> chosen = speciesForSite(settings_, {height, slope, altitude, density}, d.species, inBand);
    if (!chosen) {
      c.verdict = inBand ? Verdict::Slope : Verdict::Height;
      return c;
    }
    const SizeClass size = sizeClassFor(settings_.sizes, d.size);
    c.tree = varied(*chosen, size, {d.p.x, height, d.p.y}, d.variation);
    c.spacing = placementOf(settings_, *chosen).spacing * settings_.sizes.scale[static_cast<int>(size)];
    if (trail && trail->reaches(c.tree)) c.verdict = Verdict::Trail;  // the walkway stays free
    return c;
  };

  SplitMix64 random(SplitMix64::substream(settings_.seed, 0x7ee5ull));
  SplitMix64 sizeRandom(SplitMix64::substream(settings_.seed, 0x512eull));
  const std::int64_t darts = static_cast<std::int64_t>(kDartsPerTree * settings_.count / std::max(keptShare, 0.01)) + 1000;
  std::array<std::int64_t, 5> refused{};  // by Verdict; [Candidate]: by the spacing
  std::vector<Draws> draws(kBatchDarts);
  std::vector<Candidate> judged(kBatchDarts);
  for (std::int64_t first = 0; first < darts && static_cast<int>(trees_.size()) < settings_.count; first += kBatchDarts) {
    const int n = static_cast<int>(std::min<std::int64_t>(kBatchDarts, darts - first));
    for (Draws& d : std::span(draws).first(static_cast<size_t>(n))) {
      // z before x: the order GCC gave the dvec2 constructor's arguments when this was one
      // expression (unspecified in C++), kept so the scenes' forests stay as they were.
      d.p.y = lo.y + (hi.y - lo.y) * random.unit();
      d.p.x = lo.x + (hi.x - lo.x) * random.unit();
      d.species = random.unit();
      for (double& v : d.variation) v = random.unit();
      d.size = sizeRandom.unit();
      d.keep = stands_ ? random.unit() : 0.0;  // evenly spread: no draw
    }
    constexpr int kChunk = 1024;
    parallelFor((n + kChunk - 1) / kChunk, [&](int chunk) {
      for (int i = chunk * kChunk; i < std::min(n, (chunk + 1) * kChunk); ++i) judged[static_cast<size_t>(i)] = judge(draws[static_cast<size_t>(i)]);
    });
    // Poisson-disk condition, in dart order: no tree closer than the larger of the two spacings.
    constexpr int kCellsAhead = 16, kTreesAhead = 8;  // darts ahead whose cells, trees are fetched
    const auto site = [&](int i) { return dvec2(judged[static_cast<size_t>(i)].tree.position.x, judged[static_cast<size_t>(i)].tree.position.z); };
    const auto judgedCandidate = [&](int i) { return i < n && judged[static_cast<size_t>(i)].verdict == Verdict::Candidate; };
    for (int i = 0; i < n && static_cast<int>(trees_.size()) < settings_.count; ++i) {
      if (judgedCandidate(i + kCellsAhead)) grid.prefetchCells(site(i + kCellsAhead));
      if (judgedCandidate(i + kTreesAhead)) grid.prefetchTrees(site(i + kTreesAhead));
      const Candidate& c = judged[static_cast<size_t>(i)];
      const dvec2 p = site(i);
      if (c.verdict != Verdict::Candidate || !grid.free(p, c.spacing)) {
        ++refused[static_cast<size_t>(c.verdict)];
        continue;
      }
      grid.add(p, c.spacing);
      trees_.push_back(c.tree);
    }
  }
  const std::string why = fmt::format("darts refused: {} by the density field, {} by the height band, {} by the slope, {} by the spacing, {} by the trail",
                                      refused[1], refused[2], refused[3], refused[0], refused[4]);
  if (static_cast<int>(trees_.size()) < settings_.count)
    log::warn("vegetation: {} of {} trees fit the terrain ({})", trees_.size(), settings_.count, why);
  else
    log::debug("vegetation: placed {} trees ({})", trees_.size(), why);  // all fit: the darts matter only with FOREST_LOG=debug
}

}  // namespace forest::vegetation
