#pragma once
// Pass 4 of the frame (thesis §9.4, DESIGN §4), run only when the blur is on: the shadow term, full
// screen from the G-buffer — hardware 2×2 PCF (sampler2DShadow), (2r+1)² of them for a wider
// filter, 0 where the geometric N·L ≤ 0 before any blur. Target: RG16F (the term; the blur's
// inputs). With the blur off the lighting pass looks the term up itself (shaders/shadow_lookup.frag):
// one full-screen pass fewer.
#include <glm/glm.hpp>

#include <array>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "forest/gl/objects.hpp"
#include "forest/gl/shader.hpp"
#include "forest/render/frame.hpp"
#include "frame_block_buffer.hpp"
#include "fullscreen_triangle.hpp"
#include "geometry_pass.hpp"

namespace forest::render {

// Binds what shaders/shadow_lookup.frag reads: the G-buffer's depth and sun-facing flag, the map.
void bindShadowLookupInputs(const GBuffer& gbuffer, const gl::Texture& shadowMap);

// The lookup's filter and slices (FrameSettings::pcfRadius, the plan's slice count).
struct ShadowLookupShape {
  int pcfRadius = 0;
  int slices = 1;
  auto operator<=>(const ShadowLookupShape&) const = default;
};

// The lines that make `shape` compile-time constants of shaders/shadow_lookup.frag.
std::string shadowLookupDefines(const ShadowLookupShape& shape);

// A full-screen program that links shaders/shadow_lookup.frag, one per lookup shape, compiled when
// the shape is first used. With the filter radius and the slice count constant the lookup's loops
// unroll: read from the frame block as loop bounds, they cost the lighting pass ~7 of its ~40 ms
// (800×600, llvmpipe).
class ShadowLookupPrograms {
 public:
  // fullscreen.vert with `fragments`, shadow_lookup.frag and gbuffer_read.frag; `defines` go
  // before the shape's.
  explicit ShadowLookupPrograms(std::vector<std::string> fragments, std::string defines = "");
  // The program for `shape`, compiled now if it was not yet (Frame::render asks before its timer
  // starts, so no pass time holds a compile).
  const gl::Program& get(const ShadowLookupShape& shape);

 private:
  std::vector<std::string> fragments_;
  std::string defines_;
  std::map<ShadowLookupShape, gl::Program> programs_;
};

// The term's resolution: pixels per term texel side (FrameSettings::shadowTermScale), 1 or 2.
inline constexpr int kMaxShadowTermScale = 2;

class ShadowTermPass {
 public:
  ShadowTermPass(int width, int height);
  // Reads the lookup, the sun and the filter from the frame block; writes the term at `scale`
  // (shaders/shadow_term.frag: at every pixel, or at the nearest surface of each 2 × 2 block).
  void run(const GBuffer& gbuffer, const gl::Texture& shadowMap, const ShadowLookupShape& shape, int scale,
           const FrameBlockBuffer& frameBlock);
  void prepare(const ShadowLookupShape& shape, int scale) { programs_[index(scale)].get(shape); }  // compiles its program now
  const gl::Texture& term() const { return images_[index(lastScale_)]->texture; }  // the last run's
  int scale() const { return lastScale_; }
  // At half resolution: per block the nearest surface's window depth (written by the term pass),
  // which the blur's passes test against; null before the first half-resolution run.
  const gl::Texture* blockDepth() const { return blockDepth_ ? &*blockDepth_ : nullptr; }

 private:
  static std::size_t index(int scale) { return static_cast<std::size_t>(scale - 1); }
  int width_, height_;
  int lastScale_ = 1;
  std::array<std::optional<PassImage>, kMaxShadowTermScale> images_;  // per scale, made on first use
  std::array<ShadowLookupPrograms, kMaxShadowTermScale> programs_;
  std::optional<gl::Texture> blockDepth_;
  FullScreenTriangle triangle_;
};

}  // namespace forest::render
