#pragma once
// What one frame tells the next (beyond the papers; DESIGN §4): the record of what showed in its
// image (ImageVisibility — from the lighting pass, or from the G-buffer read back for the receiver
// mask), the guess from that image's samples moved into the next view (reprojection), whether
// chc++'s queries pay (culling::QueryPayoff), and the visible set a frozen view keeps drawing.
// Frame::render calls it at named points and nowhere else:
//   beforeCull     — takes the last record, hides what reprojection says is hidden, hands the
//                    flags to the culler and the terrain blocks, picks chc++ or frustum culling;
//   afterReadback  — records from this frame's pixels; a frame drawn by frustum culling takes its
//                    visible set from them;
//   beforeLighting, afterLighting — records from the lighting pass (without a read-back);
//   afterFrame     — the visible set, for a frozen view;
//   learn          — a frame's pass times, for the payoff.
#include <cstdint>
#include <span>
#include <vector>

#include "forest/core/camera.hpp"
#include "forest/core/scene.hpp"
#include "forest/culling/occlusion_culler.hpp"
#include "forest/culling/query_payoff.hpp"
#include "forest/gl/timing.hpp"
#include "forest/render/frame.hpp"
#include "forest/render/scene_objects.hpp"
#include "geometry_pass.hpp"
#include "image_visibility.hpp"
#include "receiver_pixels.hpp"
#include "worker_threads.hpp"

namespace forest::render {

class FrameHistory {
 public:
  FrameHistory(const SceneObjects& objects, const CullingSettings& culling);

  // How this frame culls.
  struct CullPlan {
    culling::CullingStrategy strategy = culling::CullingStrategy::ChcPlusPlus;
    bool culledByFrustum = false;  // chc++ asked, frustum culling chosen: its queries do not pay
    const std::vector<std::uint32_t>* frozenSet = nullptr;  // draw exactly these (FrameSettings::freezeCulling)
    int hiddenByReprojection = 0;
  };
  // `readsPixels`: this frame reads its G-buffer back (CasterSelection::ReceiverPixels).
  CullPlan beforeCull(std::uint64_t frameNumber, const Camera& camera, const FrameSettings& settings, bool readsPixels,
                      culling::OcclusionCuller& culler, GeometryPass& geometry);
  // After the read-back: records from its pixels; returns the frame's visible set — the culler's,
  // or for a frame drawn by frustum culling exactly the objects with pixels (and their z_f).
  const culling::CullingResult& afterReadback(const ReceiverPixels& pixels, WorkerThreads& workers, const CullPlan& plan,
                                              const culling::CullingResult& culled, const Camera& camera);
  // Per object, nonzero where it has a pixel in this frame's read-back (after afterReadback); empty
  // without the record ([culling] image_visibility off): the shadow setup's caster receivers.
  std::span<const std::uint8_t> shownInReadback() const {
    return culling_.image_visibility ? image_.shownObjects() : std::span<const std::uint8_t>{};
  }
  // Whether the lighting pass records what shows this frame (no read-back to record from).
  bool recordsInLighting(bool readsPixels) const { return culling_.image_visibility && !readsPixels; }
  void beforeLighting(FrameBlock& block, const Camera& camera) { image_.beginRecord(block, camera); }
  void afterLighting() { image_.endRecord(); }
  void afterFrame(const culling::CullingResult& visible);
  void learn(const gl::FrameTiming& timing);
  // Forgets the record and the visible set (a camera cut); what a query costs is kept.
  void forget();

  const std::vector<std::uint32_t>& visibleObjects() const { return visibleObjects_; }
  // The last record, waited for (Frame::readShownInImage); false when there is none.
  bool collectRecord() { return image_.collect(true); }
  const ImageVisibility& record() const { return image_; }

 private:
  const SceneObjects& objects_;
  CullingSettings culling_;
  ImageVisibility image_;
  culling::QueryPayoff payoff_;
  culling::CullingResult visibleFromImage_;  // the visible set of a frame frustum culling drew
  std::vector<std::uint32_t> visibleObjects_;
  bool haveVisibleSet_ = false;
};

}  // namespace forest::render
