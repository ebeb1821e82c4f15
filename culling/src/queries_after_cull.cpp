// OcclusionCuller's queries after (and, for chc++, during) a cull: the parts of the objects it
// drew (QueriesAfterTraversal: the terrain's blocks) and refineVisibleSet's second look at the
// visible set, asked against the depth drawn so far in one batch.
#include <fmt/format.h>

#include <algorithm>
#include <chrono>

#include "forest/core/error.hpp"
#include "forest/culling/occlusion_culler.hpp"
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
  if (!stateOf_) throw Error("OcclusionCuller::issueAfterCull: no frame was culled");
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
  if (used_ + groupEnds.size() > slots_) {
    // Inside a cull, results still to be read live in the buffer: reserveAfterCull made too little room.
    if (inCull_)
      throw Error(fmt::format("OcclusionCuller::issueAfterCull: {} queries after a traversal that used {} of {} slots: more "
                              "than the {} QueriesAfterTraversal::maxQueries promised", groupEnds.size(), used_, slots_, afterCullQueries_));
    // After it, the traversal read every result it needed and dropped the rest: a larger, zeroed
    // buffer loses nothing. Slots below used_ stay unused in it.
    allocateResultSlots(std::max(2 * slots_, used_ + groupEnds.size()));
    drawnSlots_ = readableSlots_ = used_;
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
      const std::uint32_t slot = takeSlot(used_, slots_);
      afterCullSlots_.push_back(slot);
      afterCullGroups_.push_back(static_cast<std::uint32_t>(g));
      afterCullGroupSlots_.push_back(slot);
      ++stats.geometryQueries;
    } else {
      afterCullSlots_.push_back(issueQuery(group));
    }
    ++stats.queriesIssued;
  }
  if (!afterCullGroups_.empty()) {
    beginQueries();
    glDepthFunc(GL_GEQUAL);  // as drawQueryBatch's geometry queries
    stats.queryTriangles += surfaces(afterCullGroups_, afterCullGroupSlots_);
    glDepthFunc(GL_GREATER);
    endQueries();
    if (batch_.empty() && !geometryQueriesPending()) markQueriesDrawn();  // else drawQueryBatch does
  }
  drawQueryBatch();
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
    afterCullVisible_[g] = afterCullSlots_[g] == kNoQuery || waitResult(afterCullSlots_[g], stats);
  endQueries();
  if (inCull_) return afterCullVisible_;  // its own clock counts this; later batches need the fences
  for (const BatchFence& f : fences_) glDeleteSync(f.fence);
  fences_.clear();
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
  batch_.reserve(boxes);
  if (stateOf_ && slots_ < 3 * stateOf_->nodes().size() + 2 + afterCullQueries_)
    allocateResultSlots(3 * stateOf_->nodes().size() + 2 + afterCullQueries_);
}

const CullingResult& OcclusionCuller::refineVisibleSet(std::span<const Aabb> objectBoxes, const QueryShapes& shapes) {
  if (!stateOf_) throw Error("OcclusionCuller::refineVisibleSet: no frame was culled");
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

void OcclusionCuller::issueAfterTraversal() {
  QueriesAfterTraversal* after = afterTraversal_;
  afterTraversal_ = nullptr;
  if (after) after->issue(*this);
}

void OcclusionCuller::issueDuringTraversal() {
  if (!afterTraversal_ || duringIssued_) return;
  if (afterTraversal_->issueDuring(*this)) {
    duringIssued_ = true;
    duringEnd_ = used_;
  }
}

void OcclusionCuller::takeDuringTraversal(CullingStats& stats, bool wait) {
  if (!duringIssued_) return;
  // Readable without a wait: deterministic, once a wait covered them (never polled); async, once
  // the fence of their batch has signalled.
  if (!wait && duringEnd_ > readableSlots_ && (queryMode_ == QueryMode::Deterministic || !resultAvailable(duringEnd_ - 1, stats)))
    return;
  duringIssued_ = false;
  const long long triangles = afterTraversal_->takeDuring(*this);  // afterCullResults ended the query state
  if (triangles > 0) {
    stats.trianglesDrawn += triangles;
    ++stats.drawCalls;
  }
}

}  // namespace forest::culling
