// CHC++ (Mattausch, Bittner, Wimmer: "CHC++: Coherent Hierarchical Culling Revisited", EG 2008).
// Async mode takes each result as soon as its batch's fence has signalled, and waits only when
// the traversal queue is empty, as the paper does (§3, "while the distance queue is empty, wait").
// Deterministic mode never polls: it takes results only when the traversal queue is empty, so a
// run traverses — and so draws and queries — the same way every time. (Taking them at fixed
// traversal steps as well, every kBatchSteps as CHC does, made llvmpipe rasterise the frame in many
// small pieces — each result read flushes its command stream — and cost the open view above the
// canopy a third of its frame.)
#include <algorithm>
#include <cmath>

#include "traversal.hpp"

namespace forest::culling {
namespace {

// §3.4: the probability that a node found invisible for i frames in a row stays invisible.
double keepProbability(int invisibleFrames) { return 0.99 - 0.7 * std::exp(-static_cast<double>(invisibleFrames)); }

// A deterministic draw in [0, n) per (node, frame): the random first re-query interval (§3.3).
std::uint64_t hashDraw(std::uint64_t node, std::uint64_t frame, std::uint64_t n) {
  std::uint64_t x = node * 0x9E3779B97F4A7C15ull ^ (frame + 0x632BE59BD9B4E019ull);
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;  // splitmix64 finaliser
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return (x ^ (x >> 31)) % n;
}

// §3.5: the boxes a node's query draws — its descendants `depth` levels down (leaves above that
// depth count as themselves) when their total area is at most `ratio` × the node box's, trying
// the deepest level first; else the node's own box. The union holds all of the node's geometry,
// so a hidden result stays exact.
// `level`, `next`, `best`: scratch lists.
// `append(n, out)`: what node n's own query draws (a leaf: its objects' query shapes).
template <class AppendBoxes>
void queryBoxes(const std::vector<BvhNode>& nodes, std::int32_t node, int depth, double ratio, std::vector<Aabb>& out,
                std::vector<std::int32_t>& level, std::vector<std::int32_t>& next, std::vector<std::int32_t>& best,
                const AppendBoxes& append) {
  const double limit = ratio * surfaceArea(nodes[node].bounds);
  level.assign(1, node);
  best.assign(1, node);
  for (int d = 1; d <= depth; ++d) {
    next.clear();
    for (std::int32_t n : level) {
      if (nodes[n].leaf()) {
        next.push_back(n);
      } else {
        next.push_back(nodes[n].left);
        next.push_back(nodes[n].right);
      }
    }
    if (next.size() == level.size()) break;  // only leaves left
    double area = 0.0;
    for (std::int32_t n : next) area += surfaceArea(nodes[n].bounds);
    if (area <= limit) best = next;
    std::swap(level, next);
  }
  // A leaf queried on its own draws its shapes; descendants standing in for a node draw their
  // boxes (their shapes would multiply the boxes of one query: 8 leaves × 4 slabs).
  if (best.size() == 1 && best.front() == node) append(node, out);
  else
    for (std::int32_t n : best) out.push_back(nodes[n].bounds);
}

// What chc++ keeps of a node from one frame to the next.
struct ChcPlusPlusNodeState : CoherentNodeState {
  int invisibleFrames = 0;           // frames found invisible in a row (p_keep's i)
  bool newlyVisible = false;         // found visible this frame (asked again next frame, then at §3.3's random interval)
  std::uint64_t nextQueryFrame = 0;  // a visible leaf is queried again from this frame
  bool geometryHidden = false;       // a leaf whose own triangles were hidden at its last query
  bool unconfirmed = false;          // found visible, then hidden at its frame's end (c-queue), and hidden since
};

// chc++: its node state and its frame (ChcPlusPlus::Frame).
class ChcPlusPlus final : public StrategyWithNodeState<ChcPlusPlusNodeState> {
 public:
  void traverse(Traversal& t) override;

 private:
  using NodeState = ChcPlusPlusNodeState;
  struct Frame;
  // The state as of the frame before, from the last image's flags (see
  // OcclusionCuller::setShownInLastImage), when chc++ did not cull that frame.
  void takeStateFromLastImage(Traversal& t);

  std::uint64_t lastFrame_ = 0;  // the last frame chc++ culled (0: none; the culler counts from 1)
};

// One chc++ frame: the paper's queues and the steps on them, as member functions over the node
// state and the traversal's query batches.
struct ChcPlusPlus::Frame {
  std::vector<NodeState>& state;
  Traversal& t;
  const std::vector<BvhNode>& nodes;
  const CullingSettings& p;
  const std::uint64_t requery;
  // The lists live in the culler's scratch (allocated once); a pending query's nodes — several for
  // a multiquery — are a range of groupNodes; drawnAlready marks a visible leaf's query (v-queue):
  // drawn this frame, it asks about the next.
  TraversalScratch& scratch;
  EntryHeap& traversal;
  FifoQueue<PendingQuery>& pending;
  std::vector<std::int32_t>& invisibleQueue;
  std::vector<std::int32_t>& visibleQueue;
  std::vector<std::int32_t>& confirmQueue;
  std::vector<std::int32_t>& renderQueue;
  std::vector<std::int32_t>& geometryQueue;
  std::vector<std::int32_t>& groupNodes;

  Frame(std::vector<NodeState>& states, Traversal& traversalState)
      : state(states),
        t(traversalState),
        nodes(traversalState.nodes()),
        p(traversalState.settings),
        requery(static_cast<std::uint64_t>(std::max(1, traversalState.settings.visible_requery_frames))),
        scratch(traversalState.scratch),
        traversal(scratch.traversal),
        pending(scratch.pending),
        invisibleQueue(scratch.invisibleQueue),
        visibleQueue(scratch.visibleQueue),
        confirmQueue(scratch.confirmQueue),
        renderQueue(scratch.renderQueue),
        geometryQueue(scratch.geometryQueue),
        groupNodes(scratch.groupNodes) {}

  void run();

  // §3.2: visible leaves wait in the render queue; it is drawn in one call before any query goes
  // out (the depth buffer must hold everything known visible) and at the end.
  void flushRender() {
    std::vector<std::uint32_t>& objects = scratch.drawList;
    objects.clear();
    for (std::int32_t n : renderQueue) {
      const auto o = t.objectsOf(n);
      objects.insert(objects.end(), o.begin(), o.end());
    }
    renderQueue.clear();
    t.drawObjects(objects);
  }
  // Before a batch of queries: what the draws held back (QueriesAfterTraversal::issueDuring) is
  // asked with it, and drawn once its results are in (takeResult), before the next batch.
  void drawBeforeQueries() {
    flushRender();
    t.parts.issueDuring();
  }
  void issue(std::span<const std::int32_t> group, bool drawnAlready) {
    std::vector<Aabb>& boxes = scratch.boxes;
    boxes.clear();
    const auto appendBoxes = [this](std::int32_t n, std::vector<Aabb>& out) { t.appendQueryBoxes(n, out); };
    for (std::int32_t n : group)
      queryBoxes(nodes, n, p.tight_box_depth, p.tight_box_area_ratio, boxes, scratch.level, scratch.next, scratch.best, appendBoxes);
    ++t.stats.queriesIssued;
    if (group.size() > 1) ++t.stats.multiQueries;
    const std::size_t slot = t.queries.issueBoxes(boxes);
    const std::size_t first = groupNodes.size();
    groupNodes.insert(groupNodes.end(), group.begin(), group.end());
    pending.push({first, group.size(), slot, drawnAlready});
  }
  void issueOne(std::int32_t n, bool drawnAlready) { issue({&n, 1}, drawnAlready); }
  // Geometry queries (beyond the paper; CullingSettings::geometry_queries): for leaves whose
  // objects the drawer can query with their own triangles.
  bool ownGeometry(std::int32_t n, QueryGeometry geometry = QueryGeometry::HullOrOwn) const {
    if (!p.geometry_queries || !nodes[n].leaf()) return false;
    for (std::uint32_t o : t.objectsOf(n))
      if (!t.drawer.queriesOwnGeometry(o, geometry)) return false;
    return true;
  }
  // Beyond the paper: a leaf whose box meets the near slab (or holds the eye) is asked with its
  // exact triangles, which the near plane clips as it clips the leaf's draw; §3.6 takes such a
  // leaf as visible without a query, since its box's (or hull's) clipped faces would miss
  // fragments. A tree beside the walker whose box reaches into the near rectangle is then drawn
  // only when a triangle of it shows.
  bool nearGeometry(std::int32_t n) const { return ownGeometry(n, QueryGeometry::Exact) && t.visibleWithoutQuery(n); }
  void issueGeometry(std::int32_t n, bool drawnAlready) {
    ++t.stats.queriesIssued;
    ++t.stats.geometryQueries;
    const std::size_t slot = t.queries.issueGeometry(t.objectsOf(n), nearGeometry(n) ? QueryGeometry::Exact : QueryGeometry::HullOrOwn);
    const std::size_t first = groupNodes.size();
    groupNodes.push_back(n);
    pending.push({first, 1, slot, drawnAlready, 0, true});
  }
  // Like the i-queue, after the render queue: the depth buffer must hold everything known visible.
  void issueGeometryQueue() {
    drawBeforeQueries();
    for (std::int32_t n : geometryQueue) issueGeometry(n, false);
    geometryQueue.clear();
  }
  // A visible leaf's query for the next frame (§3.2's v-queue): with its triangles when it can be.
  void issueVisible(std::int32_t n) {
    if (ownGeometry(n)) issueGeometry(n, true);
    else issueOne(n, true);
  }
  void issueInvisibleQueue();
  bool shownInImage(std::span<const std::uint32_t> leafObjects) const {
    for (std::uint32_t o : leafObjects)
      if (o < t.shownInLastImage.size() && t.shownInLastImage[o] != 0) return true;
    return false;
  }
  void traverseNode(std::int32_t n) {
    if (nodes[n].leaf()) {
      renderQueue.push_back(n);
    } else {
      traversal.push(t.entry(nodes[n].left));
      traversal.push(t.entry(nodes[n].right));
    }
  }
  void foundInvisible(std::int32_t n) {
    state[n].visible = false;
    state[n].invisibleFrames = std::min(state[n].invisibleFrames + 1, 1000);
  }
  void handleResult(const PendingQuery& q, bool visible);
  void takeResult() {
    const PendingQuery q = pending.front();
    pending.pop();
    handleResult(q, t.queries.waitResult(q.slot, t.stats));
    t.parts.takeDuring(t.stats, false);
  }
  // When the traversal queue is empty: the next batch of queries, or a result; false when done.
  bool onEmptyQueue();
  void visit(std::int32_t n);
  void finish();
};

// §3.1, §3.4: the i-queue goes out as one batch; with multiqueries, nodes sorted by p_keep are
// grouped greedily while the group's queries saved per query issued, |M| / (1 + (1 − Π p)·|M|),
// grows (a single node is an ordinary query: cost 1).
void ChcPlusPlus::Frame::issueInvisibleQueue() {
  if (invisibleQueue.empty()) return;
  drawBeforeQueries();
  if (!p.multiqueries) {
    for (std::int32_t n : invisibleQueue) issueOne(n, false);
    invisibleQueue.clear();
    return;
  }
  // Most often hidden first, ties in queue order (a stable sort, without the buffer
  // std::stable_sort would allocate).
  auto& order = scratch.order;
  order.clear();
  for (size_t i = 0; i < invisibleQueue.size(); ++i)
    order.push_back({-state[invisibleQueue[i]].invisibleFrames, static_cast<int>(i), invisibleQueue[i]});
  std::sort(order.begin(), order.end());
  for (size_t i = 0; i < order.size(); ++i) invisibleQueue[i] = std::get<2>(order[i]);
  auto value = [](double keepAll, size_t size) {
    return size <= 1 ? static_cast<double>(size) : static_cast<double>(size) / (1.0 + (1.0 - keepAll) * static_cast<double>(size));
  };
  std::vector<std::int32_t>& group = scratch.group;
  group.clear();
  double keepAll = 1.0;
  for (std::int32_t n : invisibleQueue) {
    const double keep = keepProbability(state[n].invisibleFrames);
    if (!group.empty() && value(keepAll * keep, group.size() + 1) <= value(keepAll, group.size())) {
      issue(group, false);
      group.clear();
      keepAll = 1.0;
    }
    group.push_back(n);
    keepAll *= keep;
  }
  if (!group.empty()) issue(group, false);
  group.clear();
  invisibleQueue.clear();
}

void ChcPlusPlus::Frame::handleResult(const PendingQuery& q, bool visible) {
  if (q.count > 1) {  // a multiquery: all hidden, or ask each node on its own
    // By index: issuing appends to groupNodes, which may move its storage.
    for (std::size_t i = q.first; i < q.first + q.count; ++i) {
      if (!visible) foundInvisible(groupNodes[i]);
      else issueOne(groupNodes[i], false);
    }
    return;
  }
  const std::int32_t n = groupNodes[q.first];
  NodeState& s = state[n];
  if (!visible) {
    foundInvisible(n);
    if (q.geometry) s.geometryHidden = true;
    if (q.drawnAlready && s.newlyVisible) s.unconfirmed = true;  // the c-queue's query failed
    return;
  }
  s.unconfirmed = false;
  const bool wasInvisible = !q.drawnAlready;
  // A box that sees something may see it through the gaps of nearer crowns: before the leaf is
  // drawn, its own triangles are asked (a late leaf was asked with them already).
  if (wasInvisible && !q.late && !q.geometry && ownGeometry(n)) {
    geometryQueue.push_back(n);
    return;
  }
  if (q.geometry) s.geometryHidden = false;
  pullUpVisibility(nodes, state, n);
  s.invisibleFrames = 0;
  if (nodes[n].leaf()) {
    // A query of a leaf not yet drawn tests this frame's depth before all of it is drawn (the
    // leaves found visible in the same batch are not drawn yet), so a leaf it finds visible may
    // be hidden in the finished image. Beyond the paper: it is drawn now and asked again once
    // everything is drawn (the c-queue, with the v-queue's last queries); only a pass there puts
    // it in the visible set. A leaf found too early is then drawn in this frame only, not in the
    // next one as well. One that passes is asked once more the next frame (it may have been
    // found late in a round of leaves that hide it next frame), and only then gets §3.3's
    // random interval. A late leaf was asked against the finished depth (but the other late
    // leaves'): it is visible, drawn after the traversal.
    if (wasInvisible && !q.late) confirmQueue.push_back(n);
    else t.markVisible(n);
  }
  if (wasInvisible) traverseNode(n);
}

bool ChcPlusPlus::Frame::onEmptyQueue() {
  if (!invisibleQueue.empty()) {
    issueInvisibleQueue();
  } else if (!geometryQueue.empty()) {
    issueGeometryQueue();
  } else if (!pending.empty()) {
    // About to wait: issue the visible leaves' queries first (§3.2), then take a result.
    if (!visibleQueue.empty()) {
      drawBeforeQueries();
      for (std::int32_t n : visibleQueue) issueVisible(n);
      visibleQueue.clear();
    }
    takeResult();
  } else {
    return false;
  }
  return true;
}

// A node taken from the traversal queue inside the frustum.
void ChcPlusPlus::Frame::visit(std::int32_t n) {
  ++t.stats.nodesVisited;
  NodeState& s = state[n];
  const bool wasVisible = s.visible && s.lastVisited + 1 == t.frame;
  // Beyond the paper: with the last image's object IDs (setShownInLastImage) a drawn leaf's
  // visibility then is known. Without a pixel it is asked before it is drawn, as a hidden leaf
  // whose triangles were hidden; with one it is drawn and needs no re-query.
  const bool imageKnown = !t.shownInLastImage.empty() && nodes[n].leaf();
  const bool hiddenInImage = wasVisible && imageKnown && !shownInImage(t.objectsOf(n));
  s.lastVisited = t.frame;
  if (t.visibleWithoutQuery(n) && !nearGeometry(n)) {  // §3.6: the camera is in (or at) the box
    pullUpVisibility(nodes, state, n);
    s.invisibleFrames = 0;
    if (nodes[n].leaf()) t.markVisible(n);
    traverseNode(n);
    return;
  }
  if (!wasVisible || hiddenInImage) {  // §3.1: wait in the i-queue for a batch
    s.visible = false;
    if (hiddenInImage) s.geometryHidden = true;
    // Beyond the paper: a leaf whose confirming query failed, hidden since, passed a query of
    // its round against a depth without the leaves found in the same round; asked again so,
    // it would be drawn again for nothing (dense stands: hundreds of trees a frame). It is
    // asked after the traversal's last draw instead, with the c-queue (no wait of its own),
    // and drawn then if it shows.
    if (!wasVisible && s.unconfirmed && nodes[n].leaf()) {
      scratch.lateQueue.push_back(n);
      return;
    }
    // Its box saw past what hid it, or meets the near slab: ask its triangles.
    if (ownGeometry(n) && (s.geometryHidden || nearGeometry(n))) {
      geometryQueue.push_back(n);
      return;
    }
    invisibleQueue.push_back(n);
    if (static_cast<int>(invisibleQueue.size()) >= p.batch_size) issueInvisibleQueue();
    return;
  }
  if (!nodes[n].leaf()) {  // opened without a query; a visible descendant pulls visibility up again
    s.visible = false;
    traverseNode(n);
    return;
  }
  // A visible leaf is drawn; it is queried again only every n_av frames (§3.3), else assumed
  // visible — with the last image's record, never.
  renderQueue.push_back(n);
  if (!imageKnown && t.frame >= s.nextQueryFrame) {
    s.visible = false;
    // §3.3: a random first interval after the confirming query spreads the re-queries of the
    // leaves that became visible together; n_av after that.
    s.nextQueryFrame = s.newlyVisible ? t.frame + 1 + hashDraw(static_cast<std::uint64_t>(n), t.frame, requery) : t.frame + requery;
    s.newlyVisible = false;
    visibleQueue.push_back(n);
  } else {
    pullUpVisibility(nodes, state, n);
    t.markVisible(n);
  }
}

// After the traversal: the remaining visible leaves' queries (for the next frame), and the
// c-queue — the leaves found visible this frame, asked against the finished depth (and again next
// frame, newlyVisible) — and the late leaves. Their results complete this frame's state and
// visible set.
void ChcPlusPlus::Frame::finish() {
  t.parts.takeDuring(t.stats, true);  // readable already: the loop's last wait covered them
  flushRender();
  for (std::int32_t n : visibleQueue) issueVisible(n);
  visibleQueue.clear();
  for (std::int32_t n : confirmQueue) {
    state[n].nextQueryFrame = t.frame + 1;
    state[n].newlyVisible = true;
    issueVisible(n);
  }
  confirmQueue.clear();
  for (std::int32_t n : scratch.lateQueue) {
    if (ownGeometry(n)) issueGeometry(n, false);
    else issueOne(n, false);
    pending.items.back().late = true;
    ++t.stats.lateQueries;
  }
  t.parts.issueAfter();  // in the same batch: answered by the same wait
  while (!pending.empty()) takeResult();
  flushRender();  // the late leaves that showed
}

void ChcPlusPlus::Frame::run() {
  if (!nodes.empty()) traversal.push(t.entry(0));
  while (true) {
    // Results: async, those the GPU has finished; deterministic, none before the traversal queue
    // runs dry (onEmptyQueue).
    if (t.queries.mode() == QueryMode::Async)
      while (!pending.empty() && t.queries.resultAvailable(pending.front().slot, t.stats)) takeResult();
    if (traversal.empty()) {
      if (!onEmptyQueue()) break;
      continue;
    }
    const std::int32_t n = traversal.top().node;
    traversal.pop();
    if (t.frustum.mayIntersect(nodes[n].bounds)) visit(n);
  }
  finish();
}

void ChcPlusPlus::takeStateFromLastImage(Traversal& t) {
  if (t.shownInLastImage.empty()) return;
  const std::vector<BvhNode>& nodes = t.nodes();
  const std::uint64_t before = t.frame - 1;
  const std::uint64_t requery = static_cast<std::uint64_t>(std::max(1, t.settings.visible_requery_frames));
  for (NodeState& s : state_) {  // hidden in that frame, as far as the image tells
    s.visible = false;
    s.lastVisited = before;
    s.invisibleFrames = std::min(s.invisibleFrames + 1, 1000);
    s.newlyVisible = s.unconfirmed = false;
  }
  for (std::size_t n = 0; n < nodes.size(); ++n) {
    if (!nodes[n].leaf()) continue;
    bool shown = false;
    for (std::uint32_t o : t.objectsOf(static_cast<std::int32_t>(n)))
      shown = shown || (o < t.shownInLastImage.size() && t.shownInLastImage[o] != 0);
    if (!shown) continue;
    NodeState& s = state_[n];
    s.invisibleFrames = 0;
    s.geometryHidden = false;
    s.nextQueryFrame = t.frame + requery;
    pullUpVisibility(nodes, state_, static_cast<std::int32_t>(n));
  }
}

void ChcPlusPlus::traverse(Traversal& t) {
  fitStateTo(t);
  // After frames chc++ did not cull (frustum culling where queries do not pay), its state is stale:
  // taken from the last image instead.
  if (lastFrame_ + 1 != t.frame) takeStateFromLastImage(t);
  lastFrame_ = t.frame;
  Frame(state_, t).run();
}

}  // namespace

std::unique_ptr<TraversalStrategy> makeChcPlusPlus() { return std::make_unique<ChcPlusPlus>(); }

}  // namespace forest::culling
