#pragma once
// Pass 5 of the frame (thesis §6.2, DESIGN §4): Phong lighting from the G-buffer with a weak
// global ambient, the shadow term (TermSource: the blur's vertical half or the half-resolution
// term's upsample when the blur is on, the lookup itself when it is off), fog and the sky colour. Targets: the lit colour (RGBA8) and, when asked, the term
// it used (RG16F).
#include <glm/glm.hpp>

#include <map>
#include <string>

#include "forest/core/scene.hpp"
#include "forest/gl/objects.hpp"
#include "forest/gl/shader.hpp"
#include "forest/render/frame.hpp"
#include "frame_block_buffer.hpp"
#include "fullscreen_triangle.hpp"
#include "geometry_pass.hpp"
#include "blur_pass.hpp"
#include "shadow_term_pass.hpp"

namespace forest::render {

// Where the lighting pass takes the shadow term from: looked up itself in the map (the blur off),
// the horizontally blurred full-resolution term (it does the vertical half), or the half-resolution
// term blurred both ways (it upsamples it).
enum class TermSource { Lookup, VerticalBlur, Upsample };

class LightingPass {
 public:
  // Tests against the G-buffer's depth (read only): lighting where something was drawn, the sky
  // (shaders/sky.frag) where nothing was.
  LightingPass(int width, int height, const GBuffer& gbuffer);
  // What selects the lighting's program: where the term comes from, the lookup's shape (Lookup),
  // the blur's tap bound (VerticalBlur, blurTapsBound), `haze` (the frame's haze density above
  // 0), `record` (record what shows: ImageVisibility::beginRecord has bound its buffer; a program
  // that can write it is slower on llvmpipe even when it does not).
  struct ProgramKey {
    TermSource source = TermSource::Lookup;
    ShadowLookupShape shape;
    int blurTaps = 0;
    bool haze = false, record = false;
    bool atHalfTermDepth = false;  // the full-screen triangle at FrameBlock::halfTerm's depth (set by run())
    auto operator<=>(const ProgramKey&) const = default;
  };
  // `term`: the blur pass's output for TermSource::VerticalBlur and Upsample, else null (the term
  // is looked up in `shadowMap`). The sun, sky, fog and blur come from the frame block.
  // `keepTerm`: also write the term used into usedTerm().
  void run(const GBuffer& gbuffer, const gl::Texture* term, const ProgramKey& key, const gl::Texture& shadowMap,
           const FrameBlockBuffer& frameBlock, bool keepTerm);
  // Compiles the program run() will use now (before any pass is timed).
  void prepare(const ProgramKey& key);

  const gl::Texture& color() const { return color_; }
  const gl::Texture& usedTerm() const { return usedTerm_; }
  const gl::Framebuffer& framebuffer() const { return framebuffer_; }

 private:
  int width_, height_;
  gl::Texture usedTerm_, color_;
  gl::Framebuffer framebuffer_;
  const gl::Program& program(const ProgramKey& key);
  // TermSource::Upsample draws twice (run()): the upsample nearer than the half-resolution term's
  // depth, the lookup beyond it.
  static ProgramKey nearHalfTermDepth(ProgramKey key);
  static ProgramKey beyondHalfTermDepth(ProgramKey key);
  std::map<ProgramKey, gl::Program> programs_;  // compiled on first use
  gl::Program sky_;
  FullScreenTriangle triangle_;
};

}  // namespace forest::render
