#include "frame_history.hpp"

namespace forest::render {

FrameHistory::FrameHistory(const SceneObjects& objects, const CullingSettings& culling)
    : objects_(objects), culling_(culling), image_(objects) {
  visibleObjects_.reserve(objects.boxes().size());  // the largest visible set: no growth per frame
  visibleFromImage_.visibleObjects.reserve(objects.boxes().size());
}

FrameHistory::CullPlan FrameHistory::beforeCull(std::uint64_t frameNumber, const Camera& camera, const FrameSettings& settings,
                                                bool readsPixels, culling::OcclusionCuller& culler, GeometryPass& geometry) {
  CullPlan plan;
  const bool frozen = settings.freezeCulling && haveVisibleSet_;
  plan.frozenSet = frozen ? &visibleObjects_ : nullptr;
  // chc++, or frustum culling where its queries do not pay ([culling] query_payoff): the visible
  // set then comes from the read-back's IDs, and so does chc++'s state when it takes over again.
  // It needs the pass times of Profiling (glFinish and a clock): llvmpipe's timer queries stamp a
  // pass when its rasteriser reaches it, after the submitting thread has binned the whole draw,
  // which would hide most of frustum culling's cost.
  const bool payoffApplies = culling_.query_payoff && culling_.image_visibility && readsPixels && !frozen &&
                             settings.timing == gl::TimingMode::Profiling;
  plan.strategy = payoffApplies ? payoff_.next(frameNumber, settings.culling) : settings.culling;
  plan.culledByFrustum = plan.strategy != settings.culling;
  // What showed in the last frame's image: read once its lighting pass is done — waited for in
  // deterministic mode, else if done already. Of those, the ones its samples moved into this view
  // say are hidden now (culling::ReprojectedImage).
  const bool shown = culling_.image_visibility && image_.collect(settings.queries == culling::QueryMode::Deterministic);
  if (shown && culling_.image_reprojection) plan.hiddenByReprojection = image_.hideByReprojection(camera);
  culler.setShownInLastImage(shown ? image_.shownObjects() : std::span<const std::uint8_t>{});
  geometry.setShownBlocksInLastImage(shown ? image_.shownBlocks() : std::span<const std::uint16_t>{});
  return plan;
}

const culling::CullingResult& FrameHistory::afterReadback(const ReceiverPixels& pixels, WorkerThreads& workers, const CullPlan& plan,
                                                          const culling::CullingResult& culled, const Camera& camera) {
  if (culling_.image_visibility)  // the cull took the last record
    image_.recordFromPixels(pixels, workers, culling_.image_reprojection);
  if (!plan.culledByFrustum) return culled;
  image_.shownAsVisibleSet(objects_.boxes(), camera, culled.stats, visibleFromImage_);  // exactly the objects with pixels
  return visibleFromImage_;
}

void FrameHistory::afterFrame(const culling::CullingResult& visible) {
  visibleObjects_ = visible.visibleObjects;
  haveVisibleSet_ = true;
}

void FrameHistory::learn(const gl::FrameTiming& timing) {
  for (const gl::PassTime& pass : timing.passes)
    if (kFramePassNames.find(pass.pass) == FramePass::Geometry) payoff_.record(timing.frame, pass.ms);
}

void FrameHistory::forget() {
  image_.forget();
  haveVisibleSet_ = false;
}

}  // namespace forest::render
