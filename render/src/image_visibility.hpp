#pragma once
// What showed in the last lit image, for the next frame's culling (beyond CHC++; [culling]
// image_visibility). The lighting pass reads every pixel's G-buffer texel anyway; it writes the
// frame's stamp into a slot of its object (the ID) and, on terrain, of its block
// (shaders/lighting.frag, recordShown). The next frame reads the slots back once that pass has
// finished: an object or block drawn then had a pixel exactly when its slot holds that stamp.
// CHC's assumption of coherence (§3.3's n_av frames without a query) stands in for exactly this
// knowledge, and one frame late at best: a tree drawn without a pixel was drawn again for up to
// n_av frames. With the record it is asked before it is drawn again, and a tree with a pixel needs
// no re-query. Exact either way: the record only decides between drawing untested what showed
// and asking first.
// Where the frame reads the G-buffer back anyway (CasterSelection::ReceiverPixels: a software
// renderer), the record is taken from that read on the CPU instead (recordFromPixels), and the
// lighting pass is compiled without it: on llvmpipe a fragment shader that writes a buffer at all
// cost the thesis walk's lighting pass ~2.2 ms of its ~9.5 (800 × 600), the CPU record ~0.5 ms.
// Both record the same objects; a pixel within rounding of a block's edge may mark the neighbour
// in either. The record from pixels also keeps a sample of the image, its eye depths and objects
// (every culling::ReprojectedImage::kSampleStride-th pixel of every such row), so that the next
// frame can guess which objects that showed are hidden in its view (hideByReprojection;
// culling::ReprojectedImage).
#include <cstdint>
#include <span>
#include <vector>

#include "forest/core/camera.hpp"
#include "forest/culling/occlusion_culler.hpp"
#include "forest/culling/reprojected_image.hpp"
#include "forest/gl/objects.hpp"
#include "forest/render/scene_objects.hpp"
#include "forest/render/uniform_blocks.hpp"
#include "receiver_pixels.hpp"
#include "worker_threads.hpp"

namespace forest::render {

class ImageVisibility {
 public:
  explicit ImageVisibility(const SceneObjects& objects);
  ~ImageVisibility();
  ImageVisibility(const ImageVisibility&) = delete;
  ImageVisibility& operator=(const ImageVisibility&) = delete;

  // Before the lighting pass: a new stamp into the frame block (FrameBlock::imageRecord,
  // imageTerrain, with the eye's terrain position) and the record's buffer bound (binding 7).
  void beginRecord(FrameBlock& block, const Camera& camera);
  // After the lighting pass's draw: fenced, so that collect() knows when it is complete.
  void endRecord();
  // Instead of beginRecord … endRecord: the record from the frame's G-buffer as read back (the
  // same flags; complete at once). Call it after this frame's culling has taken the last flags.
  // `workers` share out the rows.
  // `keepSamples`: also keep the image's samples for hideByReprojection ([culling] image_reprojection).
  void recordFromPixels(const ReceiverPixels& pixels, WorkerThreads& workers, bool keepSamples);
  // Before the next frame's culling: whether the last record is complete — waiting for it with
  // `wait`, else one poll of its fence — and then its flags (shownObjects, shownBlocks). False
  // when nothing was recorded since the last forget() or it is not complete: no flags.
  bool collect(bool wait);
  // Per object: 1 when it had a pixel (culling::OcclusionCuller::setShownInLastImage).
  std::span<const std::uint8_t> shownObjects() const { return shownObjects_; }
  // The record from pixels as this frame's visible set (a frame drawn by frustum culling,
  // culling::QueryPayoff): exactly the objects with a pixel, and z_f from their boxes; `stats`
  // taken as they are.
  void shownAsVisibleSet(std::span<const Aabb> objectBoxes, const Camera& camera, const culling::CullingStats& stats,
                         culling::CullingResult& out) const;
  // Per tile: bit b when its block b of the 4 × 4 at levels 0–3 had a pixel
  // (TerrainBlockVisibility::setShownInLastImage).
  std::span<const std::uint16_t> shownBlocks() const { return shownBlocks_; }
  // Drops the last record (a camera cut).
  void forget();
  // After collect(), with a record from pixels: clears the flags of the trees and props whose
  // samples of that image, moved into `next`'s view, are all behind others' (render ahead of
  // chc++: asked before they are drawn again). Returns how many; 0 without samples.
  int hideByReprojection(const Camera& next);

 private:
  const SceneObjects& objects_;
  std::size_t blockSlots_ = 0;      // the first block's slot: after the sky's 0 and every object's ID
  gl::ReadMappedStamps record_;     // one stamp per slot
  std::uint32_t stamp_ = 0;         // the last record's (0: none)
  GLsync fence_ = nullptr;          // the last record's lighting pass
  bool fromPixels_ = false;         // the flags hold a record from pixels not collected yet
  std::vector<std::uint8_t> shownObjects_;
  std::vector<std::uint16_t> shownBlocks_;
  // recordFromPixels: row y's objects and blocks into `objects`, `blocks`; the other bands' flags.
  void markRow(const ReceiverPixels& pixels, int y, std::vector<std::uint8_t>& objects, std::vector<std::uint16_t>& blocks) const;
  // Row y's samples (every culling::ReprojectedImage::kSampleStride-th pixel) into samples_ (y a
  // multiple of the stride; bands write their own rows).
  void sampleRow(const ReceiverPixels& pixels, int y);
  std::vector<std::vector<std::uint8_t>> bandObjects_;
  std::vector<std::vector<std::uint16_t>> bandBlocks_;
  culling::SampledImage samples_;  // the last record's
  bool haveSamples_ = false;       // samples_ belong to a record not guessed from yet
  culling::ReprojectedImage reprojected_;
};

}  // namespace forest::render
