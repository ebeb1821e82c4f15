// OcclusionCuller's queries after (and, for chc++, during) a cull: the parts of the objects it
// drew (QueriesAfterTraversal: the terrain's blocks) and refineVisibleSet's second look at the
// visible set, asked against the depth drawn so far in one batch.
#include <fmt/format.h>

#include <algorithm>
#include <chrono>

#include "forest/core/error.hpp"
#include "forest/culling/occlusion_culler.hpp"
#include "query_batches.hpp"
#include "traversal.hpp"

namespace forest::culling {

const std::vector<bool>& OcclusionCuller::queryAfterCull(std::span<const Aabb> boxes, std::span<const std::uint32_t> groupEnds,
                                                         const SurfaceQueries& surfaces) {
  issueAfterCull(boxes, groupEnds, surfaces);
  return afterCullResults();
}

namespace {
constexpr std::size_t kNoQuery = ~std::size_t{0};  // a group visible without a query
}  // namespace

void OcclusionCuller::issueAfterCull(std::span<const Aabb> boxes, std::span<const std::uint32_t> groupEnds,
                                     const SurfaceQueries& surfaces, std::span<const std::uint8_t> bySurface) {
  if (!culledBvh_) throw Error("OcclusionCuller::issueAfterCull: no frame was culled");
  if (afterCullIssued_) throw Error("OcclusionCuller::issueAfterCull: the previous queries' results were not taken");
  for (std::size_t g = 0; g < groupEnds.size(); ++g)
    if (groupEnds[g] > boxes.size() || (g > 0 && groupEnds[g] < groupEnds[g - 1]))
      throw Error(fmt::format("OcclusionCuller::queryAfterCull: group {} ends at box {}: expected ends that do not decrease, "
                              "within the {} boxes", g, groupEnds[g], boxes.size()));
  if (!bySurface.empty() && (!surfaces || bySurface.size() != groupEnds.size()))
    throw Error(fmt::format("OcclusionCuller::issueAfterCull: {} surface flags for {} groups{}", bySurface.size(), groupEnds.size(),
                            surfaces ? "" : " and no surfaces to draw"));
  afterCullIssued_ = true;
  afterCullSlots_.clear();
  afterCullVisible_.assign(groupEnds.size(), false);
  if (groupEnds.empty()) return;
  const auto start = std::chrono::steady_clock::now();
  CullingStats& stats = result_.stats;
  QueryBatches& queries = *queries_;
  if (queries.used() + groupEnds.size() > queries.capacity()) {
    // Inside a cull, results still to be read live in the buffer: reserveAfterCull made too little room.
    if (inCull_)
      throw Error(fmt::format("OcclusionCuller::issueAfterCull: {} queries after a traversal that used {} of {} slots: more "
                              "than the {} QueriesAfterTraversal::maxQueries promised", groupEnds.size(), queries.used(),
                              queries.capacity(), afterCullQueries_));
    // After it, the traversal read every result it needed and dropped the rest: a larger, zeroed
    // buffer loses nothing. The slots in use stay unused in it.
    queries.growAfterFrame(std::max(2 * queries.capacity(), queries.used() + groupEnds.size()));
  }
  afterCullGroups_.clear();
  afterCullGroupSlots_.clear();
  const NearSlab nearSlab(camera_);
  std::uint32_t first = 0;
  for (std::size_t g = 0; g < groupEnds.size(); ++g) {
    const std::span<const Aabb> group = boxes.subspan(first, groupEnds[g] - first);
    first = groupEnds[g];
    if (std::any_of(group.begin(), group.end(), [&](const Aabb& b) { return boxVisibleWithoutQuery(b, camera_, nearSlab); })) {
      afterCullSlots_.push_back(kNoQuery);
      continue;
    }
    if (surfaces && (bySurface.empty() || bySurface[g] != 0)) {
      const std::size_t slot = queries.takeSlot();
      afterCullSlots_.push_back(slot);
      afterCullGroups_.push_back(static_cast<std::uint32_t>(g));
      afterCullGroupSlots_.push_back(static_cast<std::uint32_t>(slot));
      ++stats.geometryQueries;
    } else {
      afterCullSlots_.push_back(queries.issueBoxes(group));
    }
    ++stats.queriesIssued;
  }
  if (!afterCullGroups_.empty()) {
    queries.beginQueryState();
    glDepthFunc(GL_GEQUAL);  // as QueryBatches::drawBatch's geometry queries
    stats.queryTriangles += surfaces(afterCullGroups_, afterCullGroupSlots_);
    glDepthFunc(GL_GREATER);
    queries.endQueryState();
    if (!queries.batchPending()) queries.markDrawn();  // else drawBatch does
  }
  queries.drawBatch(stats);
  // Inside a cull its own clock counts this.
  if (!inCull_) stats.cpuMilliseconds += 1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

const std::vector<bool>& OcclusionCuller::afterCullResults() {
  if (!afterCullIssued_) throw Error("OcclusionCuller::afterCullResults: no queries were issued after the cull");
  afterCullIssued_ = false;
  const auto start = std::chrono::steady_clock::now();
  CullingStats& stats = result_.stats;
  const double waitedBefore = stats.waitMilliseconds;
  for (std::size_t g = 0; g < afterCullSlots_.size(); ++g)
    afterCullVisible_[g] = afterCullSlots_[g] == kNoQuery || queries_->waitResult(afterCullSlots_[g], stats);
  queries_->endQueryState();
  if (inCull_) return afterCullVisible_;  // its own clock counts this; later batches need the fences
  queries_->dropFences();
  stats.cpuMilliseconds += 1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() -
                           (stats.waitMilliseconds - waitedBefore);
  return afterCullVisible_;
}

void OcclusionCuller::reserveAfterCull(std::size_t queries, std::size_t boxes) {
  afterCullQueries_ = std::max(afterCullQueries_, queries);
  afterCullSlots_.reserve(queries);
  afterCullGroups_.reserve(queries);
  afterCullGroupSlots_.reserve(queries);
  refineEnds_.reserve(queries);
  afterCullVisible_.reserve(queries);
  refineBoxes_.reserve(boxes);
  queries_->reserveBatch(boxes, 0);
  if (culledBvh_) queries_->reserveSlots(QueryBatches::slotsForFrame(culledNodes_, afterCullQueries_));
}

const CullingResult& OcclusionCuller::refineVisibleSet(std::span<const Aabb> objectBoxes, const QueryShapes& shapes) {
  if (!culledBvh_) throw Error("OcclusionCuller::refineVisibleSet: no frame was culled");
  std::vector<std::uint32_t>& visible = result_.visibleObjects;
  refineBoxes_.clear();
  refineEnds_.clear();
  for (std::uint32_t o : visible) {
    if (o >= objectBoxes.size() || (!shapes.empty() && o >= shapes.ranges.size()))
      throw Error(fmt::format("OcclusionCuller::refineVisibleSet: object {} has no box", o));
    if (shapes.empty() || shapes.ranges[o].count == 0) {
      refineBoxes_.push_back(objectBoxes[o]);
    } else {
      const auto first = shapes.boxes.begin() + shapes.ranges[o].first;
      refineBoxes_.insert(refineBoxes_.end(), first, first + shapes.ranges[o].count);
    }
    refineEnds_.push_back(static_cast<std::uint32_t>(refineBoxes_.size()));
  }
  const std::vector<bool>& passed = queryAfterCull(refineBoxes_, refineEnds_);
  std::size_t kept = 0;
  for (std::size_t i = 0; i < visible.size(); ++i)
    if (passed[i]) visible[kept++] = visible[i];
  visible.resize(kept);
  result_.farDepth = farDepthOf(visible, objectBoxes, camera_);
  return result_;
}

void PartQueries::start(OcclusionCuller& culler, QueryBatches& queries, QueriesAfterTraversal* after) {
  culler_ = &culler;
  queries_ = &queries;
  after_ = after;
  duringIssued_ = false;
}

void PartQueries::issueAfter() {
  QueriesAfterTraversal* after = after_;
  after_ = nullptr;
  if (after) after->issue(*culler_);
}

void PartQueries::issueDuring() {
  if (!after_ || duringIssued_) return;
  if (after_->issueDuring(*culler_)) {
    duringIssued_ = true;
    duringEnd_ = queries_->used();
  }
}

void PartQueries::takeDuring(CullingStats& stats, bool wait) {
  if (!duringIssued_) return;
  // Readable without a wait: deterministic, once a wait covered them (never polled); async, once
  // the fence of their batch has signalled.
  if (!wait && duringEnd_ > queries_->readable() &&
      (queries_->mode() == QueryMode::Deterministic || !queries_->resultAvailable(duringEnd_ - 1, stats)))
    return;
  duringIssued_ = false;
  const long long triangles = after_->takeDuring(*culler_);  // afterCullResults ended the query state
  if (triangles > 0) {
    stats.trianglesDrawn += triangles;
    ++stats.drawCalls;
  }
}

}  // namespace forest::culling
