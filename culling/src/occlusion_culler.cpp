#include "forest/culling/occlusion_culler.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>

#include "forest/core/error.hpp"
#include "query_batches.hpp"
#include "traversal.hpp"

namespace forest::culling {

namespace {

// One row per strategy: a new strategy is its enum value and name, its file under src/ (a
// TraversalStrategy) and a row here.
struct StrategyRow {
  CullingStrategy strategy;
  std::unique_ptr<TraversalStrategy> (*make)();
  // Whether it asks each leaf it found visible in a frame again once everything it drew is drawn
  // (confirmsFoundLeaves).
  bool confirmsFoundLeaves;
};
constexpr std::array<StrategyRow, 5> kStrategies{{
    {CullingStrategy::None, [] { return makeFrustumCulling(false); }, false},
    {CullingStrategy::Frustum, [] { return makeFrustumCulling(true); }, false},
    {CullingStrategy::StopAndWait, makeStopAndWait, false},
    {CullingStrategy::Chc, makeChc, false},
    {CullingStrategy::ChcPlusPlus, makeChcPlusPlus, true},
}};

const StrategyRow& rowOf(CullingStrategy strategy) {
  for (const StrategyRow& row : kStrategies)
    if (row.strategy == strategy) return row;
  throw Error(fmt::format("OcclusionCuller: culling strategy {} has no row", static_cast<int>(strategy)));
}

}  // namespace

double farDepthOf(std::span<const std::uint32_t> objects, std::span<const Aabb> objectBoxes, const Camera& camera) {
  const glm::dmat4 view = camera.view();
  double farDepth = camera.near;
  for (std::uint32_t o : objects) farDepth = std::max(farDepth, depthRange(objectBoxes[o], view).second);
  return std::min(farDepth, camera.far);
}

bool confirmsFoundLeaves(CullingStrategy strategy) { return rowOf(strategy).confirmsFoundLeaves; }

OcclusionCuller::~OcclusionCuller() = default;
OcclusionCuller::OcclusionCuller(OcclusionCuller&&) noexcept = default;
OcclusionCuller& OcclusionCuller::operator=(OcclusionCuller&&) noexcept = default;

OcclusionCuller::OcclusionCuller()
    : queries_(std::make_unique<QueryBatches>()),
      scratch_(std::make_unique<TraversalScratch>()),
      parts_(std::make_unique<PartQueries>()) {}

TraversalStrategy& OcclusionCuller::strategyUnit(CullingStrategy strategy) {
  const std::size_t i = static_cast<std::size_t>(&rowOf(strategy) - kStrategies.data());
  if (!strategies_[i]) strategies_[i] = kStrategies[i].make();
  return *strategies_[i];
}

void OcclusionCuller::reset() {
  for (auto& strategy : strategies_)
    if (strategy) strategy->forget();
  culledBvh_ = nullptr;
}

void OcclusionCuller::beginCull(const Bvh& bvh, const Camera& camera, const QueryShapes& shapes, ObjectDrawer& drawer,
                                QueriesAfterTraversal* after) {
  result_.stats = CullingStats{};
  result_.visibleObjects.clear();
  scratch_->clear();
  ++frame_;
  afterCullIssued_ = false;
  camera_ = camera;
  queries_->beginFrame(frame_, camera, drawer, queryMode_);
  if (culledBvh_ != &bvh || culledNodes_ != bvh.nodes().size()) {
    reset();  // another BVH: no node state carries over
    culledBvh_ = &bvh;
    culledNodes_ = bvh.nodes().size();
    scratch_->reserve(bvh.nodes().size(), bvh.objectCount(), shapes.boxes.size(), result_.visibleObjects);
    queries_->reserveSlots(QueryBatches::slotsForFrame(bvh.nodes().size(), afterCullQueries_));
    queries_->reserveBatch(0, bvh.objectCount());
  }
  if (after && after->maxQueries() > afterCullQueries_) reserveAfterCull(after->maxQueries(), 0);
  parts_->start(*this, *queries_, after);
  inCull_ = true;
}

const CullingResult& OcclusionCuller::cull(const Bvh& bvh, std::span<const Aabb> objectBoxes, const Camera& camera,
                                           CullingStrategy strategy, ObjectDrawer& drawer, const QueryShapes& shapes,
                                           QueriesAfterTraversal* after) {
  if (!shapes.empty() && shapes.ranges.size() != objectBoxes.size())
    throw Error(fmt::format("OcclusionCuller: query shapes for {} objects, expected {}", shapes.ranges.size(), objectBoxes.size()));
  if (objectBoxes.size() != bvh.objectCount())
    throw Error(fmt::format("OcclusionCuller: {} object boxes for a BVH over {}", objectBoxes.size(), bvh.objectCount()));
  const auto start = std::chrono::steady_clock::now();
  CullingResult& result = result_;
  TraversalStrategy& unit = strategyUnit(strategy);
  beginCull(bvh, camera, shapes, drawer, after);
  Traversal t{bvh,        camera, Frustum(camera), drawer, result.stats, result.visibleObjects, *scratch_, shapes, parameters_,
              NearSlab(camera), *queries_, *parts_, frame_, shownInLastImage_};
  unit.traverse(t);
  parts_->issueAfter();  // chc++ did before its last wait
  queries_->endFrame(result.stats);
  shownInLastImage_ = {};  // setShownInLastImage's flags are for one cull
  inCull_ = false;
  if (!afterCullIssued_) queries_->dropFences();  // else afterCullResults may still need them
  result.stats.stateSwitches = queries_->stateSwitches();

  std::vector<std::uint32_t>& visible = t.visible;
  std::sort(visible.begin(), visible.end());
  visible.erase(std::unique(visible.begin(), visible.end()), visible.end());
  result.farDepth = farDepthOf(visible, objectBoxes, camera);
  result.stats.cpuMilliseconds =
      1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() - result.stats.waitMilliseconds;
  return result;
}

}  // namespace forest::culling
