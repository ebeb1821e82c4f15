#pragma once
// The frame (DESIGN §1, §4; thesis §5.1, §6.2, §9.3), for a host program: scene in, image and
// statistics out.
//   1. geometry pass — the culling traversal draws the G-buffer: depth, albedo, shading and
//      geometric normals, object ID; the visible set gives z_f and the shadow receivers;
//   2. shadow setup from the visible set (uniform, uniform-stable, lispsm, tsm, tsm-iterative),
//      per slice of the visible depth range when z-partitioned (cascades, DESIGN §4);
//   3. shadow pass — only the selected casters, front faces culled (backside rendering), into a
//      float depth map (one layer of an array per slice); casters drawn at the eye's LOD;
//   4. shadow term — from the G-buffer, hardware 2×2 PCF (sampler2DShadow), 0 where the geometric
//      N·L ≤ 0, at half resolution (or full: shadowTermScale); then the depth-aware eye-space blur
//      (separable, shrinking with depth): both halves at half resolution, the horizontal one at
//      full; both only with the blur on;
//   5. lighting — the term upsampled within the depth where the blur is 2 px wide and looked up
//      beyond (at full resolution: the blur's vertical pass; the blur off: looked up), Phong with a
//      weak global ambient, haze; the sky where nothing was drawn.
// Eye → light matrices are composed in double, camera-relative.
#include <array>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "forest/core/camera_path.hpp"
#include "forest/core/enum_names.hpp"
#include "forest/core/frame_passes.hpp"
#include "forest/core/image.hpp"
#include "forest/core/scene.hpp"
#include "forest/culling/bvh.hpp"
#include "forest/culling/occlusion_culler.hpp"
#include "forest/gl/objects.hpp"
#include "forest/gl/context.hpp"
#include "forest/gl/shader.hpp"
#include "forest/gl/timing.hpp"
#include "forest/render/scene_objects.hpp"
#include "forest/shadows/cascades.hpp"
#include "forest/shadows/kept_slices.hpp"
#include "forest/shadows/shadow_setup.hpp"

namespace forest::render {

// Which objects the shadow pass draws.
enum class CasterSelection {
  Receivers,    // box swept along the light meets a visible receiver's box (shadows/casters.hpp)
  FrustumBody,  // box meets the focus body B of the whole view frustum
  All,          // every object
  // As Receivers, then kept only when the box, projected into the map and grown by the filter's
  // reach, covers a visible sun-facing pixel farther from the light (shadows::ReceiverMask, Bittner
  // et al. 2011 §4). The pixels are read back from the G-buffer: the CPU waits for the geometry
  // pass (a sync point a GPU frame otherwise avoids, DESIGN §9).
  ReceiverPixels,
  // As Receivers, then each tree kept only when one of its height slabs, in the map and grown by
  // the filter's reach, covers a sun-facing pixel farther from the light — tested on the GPU
  // against a receiver mask built there from the G-buffer (render/src/gpu_caster_filter.hpp):
  // nothing is read back, the shadow pass draws what the GPU kept by indirect draws.
  ReceiverMaskGpu,
};
inline constexpr EnumNames<CasterSelection, 5> kCasterSelectionNames{
    "caster selection", {{{CasterSelection::Receivers, "receivers"}, {CasterSelection::ReceiverPixels, "receiver-pixels"},
                          {CasterSelection::ReceiverMaskGpu, "receiver-mask-gpu"}, {CasterSelection::FrustumBody, "frustum-body"},
                          {CasterSelection::All, "all"}}}};

// The read-back path's trees hidden from the sun (render/src/caster_occlusion.hpp): culled between
// two draws of each layer (the layer read back between them), drawn with the rest, or culled where
// the trees it could leave out outweigh the read-backs and their test (CasterOcclusion::worthCulling).
// FrameSettings::impostorDistance: the distance where an impostor errs by at most a pixel.
inline constexpr double kImpostorDistanceAuto = -1.0;

enum class HiddenCasters { Auto, Cull, Draw };
inline constexpr EnumNames<HiddenCasters, 3> kHiddenCastersNames{
    "hidden casters", {{{HiddenCasters::Auto, "auto"}, {HiddenCasters::Cull, "cull"}, {HiddenCasters::Draw, "draw"}}}};

// What bounds the focus body B: the visible receivers (their box, and the visible set's z_f as
// the far distance; thesis §9.2.5, DESIGN §4) or the whole view frustum within the scene (V ∩ S,
// eq. 4.2, the camera's own far plane).
enum class FocusBound { Receivers, Frustum };
inline constexpr EnumNames<FocusBound, 2> kFocusBoundNames{
    "focus bound", {{{FocusBound::Receivers, "receivers"}, {FocusBound::Frustum, "frustum"}}}};

struct FrameSettings {
  shadows::ShadowMethod method = shadows::ShadowMethod::Lispsm;
  int shadowMapSize = 2048;       // texels per side, [512, 8192]
  double slopeScaleBias = 0.0;    // glPolygonOffset factor in the shadow pass (0: none)
  bool backside = true;           // cull front faces in the shadow pass (thesis §5.1)
  culling::CullingStrategy culling = culling::CullingStrategy::ChcPlusPlus;
  // Inspection (window mode): keep the previous frame's visible set — the geometry pass draws
  // exactly it, without culling, and z_f, B and the casters follow from it — while the camera
  // moves, to see what was culled. The first frame culls normally.
  bool freezeCulling = false;
  CasterSelection casters = CasterSelection::Receivers;
  FocusBound focus = FocusBound::Receivers;
  int pcfRadius = 0;              // 0: hardware 2×2 PCF; r: (2r+1)² hardware lookups, [0, 4]
  // Eye-space blur of the shadow term (thesis §6.3, §9.4.2): radius in pixels for surfaces up to
  // blurReferenceDepth away, shrinking as 1/z beyond; 0 = off. [0, 16].
  double blurRadius = 0.0;
  double blurReferenceDepth = 10.0;  // metres, > 0
  // With the blur on, the shadow term's resolution: pixels per term texel side. 1: a term at every
  // pixel, the blur's vertical half inside the lighting pass; 2: a term at the nearest surface of
  // each 2 × 2 block, both blur halves on a quarter of the pixels, and a depth-aware upsample in the
  // lighting pass (render/src/shadow_term_pass.hpp; the CLI's default, --term-resolution half).
  // The blur off, lighting looks the term up at every pixel either way.
  int shadowTermScale = 1;
  std::optional<double> fogDensity;  // distance haze per metre, [0, 1] (0: none); unset: the scene's [render] haze
  // Error injection for validating the error figures (ground truth tests): the shadow-term lookup
  // reads the map this many texels off in x and y. 0 in normal use.
  glm::dvec2 lookupShiftTexels{0.0};
  // Z-partitioning (DESIGN §4, Zhang et al. 2006): the visible depth range [z_near, z_f] split into
  // this many slices, each with its own focus body, setup, casters and map layer of shadowMapSize²
  // (1: one map); unset: the scene's [shadows]. λ of the split scheme, [0, 1]; the blend band at a
  // split, as a share of its distance, [0, 0.5].
  std::optional<int> cascades;
  std::optional<double> splitLambda;
  std::optional<double> cascadeBlend;
  // Unequal layers (issue "Shadows that hold still", item 4): with K > 1 slices the last one's
  // layer has round(farSliceScale · shadowMapSize) texels per side, the others shadowMapSize. The
  // layers share one array texture as large as the largest; a smaller layer is the square at its
  // origin (sliceMapSize). [0.5, 2]; 1: equal layers. Not with the GPU's caster filter (its masks
  // are of the layers' one size).
  double farSliceScale = 1.0;
  // How the passes are timed (DESIGN §9): Profiling brackets each pass with glFinish and a steady
  // clock (llvmpipe, where timer queries lie; the pipeline is serialised); GpuQueries puts
  // GL_TIMESTAMP queries around each pass and reads them frames later, so nothing in a frame waits
  // for the GPU — the pass times of frame k arrive in a later frame (Frame::takePassTimes).
  gl::TimingMode timing = gl::TimingMode::Profiling;
  // How CHC and CHC++ read their occlusion queries (culling/occlusion_culler.hpp): at fixed
  // traversal steps (deterministic: the same visible set every run) or when available (async).
  culling::QueryMode queries = culling::QueryMode::Deterministic;
  // The lighting pass also writes the shadow term it lit with, for readShadowTerm (the blur off)
  // and readBlurredShadowTerm. Runs that only time or show frames (walkthrough, budget, stress,
  // window) turn it off: one render target less (0.2–0.3 ms of the 800 × 600 lighting pass on
  // llvmpipe, thesis walk).
  bool keepShadowTerm = true;
  // The shadow pass draws its casters into the whole map, for readShadowMap (debug images, the
  // truth's flicker probes). Off (the walkthrough's runs), with the receiver pixels known
  // (CasterSelection::ReceiverPixels), it draws them only into the texels this frame's lookups can
  // read (ShadowSlice::texelsRead, ~60% of the map along the thesis walk); the rest stays cleared.
  bool wholeShadowMap = true;
  // Kept slices (shadows/kept_slices.hpp): each slice keeps its map's matrices while this frame's
  // focus body fits in them and its texels stay within the limits; refits cover a margin with the
  // warp snapped. Off: every slice refits to the view every frame. Off here (a frame on its own,
  // the tests); the command line's --keep-slices is on unless asked otherwise.
  bool keepSlices = false;
  shadows::KeepLimits keepLimits;
  // With CasterSelection::ReceiverPixels and caching off: whether the trees hidden from the sun are
  // culled (HiddenCasters): the same term, fewer trees, two read-backs of each layer drawn.
  HiddenCasters hiddenCasters = HiddenCasters::Auto;
  // Far trees as impostors (issue "Far trees as impostors"; TreeRenderer, ImpostorAtlas): beyond
  // impostorDistance metres from the eye to a tree's base, over its size class's scale (as the LOD
  // bands), the tree is drawn — in the G-buffer and in the shadow map — by its impostor baked from
  // its species' LOD0 (at the first frame that asks), cross-faded from its mesh over impostorBand ×
  // the distance. 0: meshes only; kImpostorDistanceAuto: where an impostor's largest error covers
  // at most one pixel of the frame (ImpostorAtlas::switchDistance). Not with cached slices.
  double impostorDistance = 0.0;
  double impostorBand = 0.1;
  // Cached slices (render/src/slice_cache.hpp): a layer that still holds what its slice needs —
  // the same matrices (a kept slice), the casters drawn then, none moved by a texel — is not
  // redrawn. Layers are then drawn whole (no scissor), and the GPU's caster filter disables it.
  bool cacheSlices = false;
  // With cacheSlices, a staggered schedule: slice k keeps held casters that changed (a LOD, a
  // morph, the wind) for up to 2^k − 1 frames after its layer's clear (slice 0: none).
  bool staggerSlices = false;
};

// With the term at half resolution (shadowTermScale 2), the eye depth (m) nearer than which
// lighting upsamples it: where the blur's radius R · z_ref / z falls to 2 pixels. Beyond, lighting
// looks the term up at every pixel.
double halfTermSplitDepth(const FrameSettings& settings);

// Deterministic queries on a software renderer, async on a hardware one (the default of --queries).
culling::QueryMode defaultQueryMode(const gl::ContextInfo& info);

// Receiver pixels on a software renderer, receiver boxes on a hardware one (the default of
// --casters). On llvmpipe the read-back costs no GPU time (the rasteriser's threads sit idle while
// the CPU sets up the shadows either way) and the mask's fewer casters save more than it costs
// (docs/design.md); a GPU would stall on the read-back (DESIGN §9).
CasterSelection defaultCasterSelection(const gl::ContextInfo& info);

// Profiling on a software renderer, timer queries on a hardware one (the default of --timing).
gl::TimingMode defaultTimingMode(const gl::ContextInfo& info);

// The cascades a frame uses: the settings' where given, else the scene's [shadows].
ShadowSettings resolveCascades(const FrameSettings& settings, const Scene& scene);

// Texels per side of slice `slice`'s layer of `cascades`: shadowMapSize, the last of several
// slices round(farSliceScale · shadowMapSize).
int sliceMapSize(const FrameSettings& settings, int slice, int cascades);
// The texels of all `cascades` layers (what "equal total texels" compares).
long long shadowTexels(const FrameSettings& settings, int cascades);
// The layers as a user reads them: "2048²", "4×1024²", "3×894²+1341²".
std::string shadowLayoutLabel(const FrameSettings& settings, int cascades);

// One slice of a z-partitioned frame: the eye depths it serves, its shadow setup's n and γ, what
// its layer drew.
enum class SliceUpdate { Reuse, Add, Redraw };  // what the shadow pass did with a layer (cached slices)
inline constexpr EnumNames<SliceUpdate, 3> kSliceUpdateNames{
    "slice update", {{{SliceUpdate::Reuse, "reuse"}, {SliceUpdate::Add, "add"}, {SliceUpdate::Redraw, "redraw"}}}};

struct CascadeStats {
  double fromM = 0.0, toM = 0.0;  // eye depths: pixels in [from, to) read this slice's layer
  double n = 0.0, gammaDeg = 0.0; // the setup's (0 for uniform methods' n)
  int mapSize = 0;                // its layer's texels per side (sliceMapSize)
  int casters = 0;
  long long triangles = 0;
  long long texelsDrawn = 0;      // texels of its layer the shadow pass drew its casters into (ShadowSlice::texelsRead)
  double shadowMs = 0.0;          // its share of the shadow pass (Profiling timing; 0 with GpuQueries)
  shadows::SliceKeeping keeping;  // kept slices: whether its map was kept, for how many frames, why not
  // Cached slices: whether its layer was reused as it was, had the casters it lacked added, or was
  // cleared and redrawn, and why ("" when reused; "off", "empty", or SliceCache::plan's reason).
  SliceUpdate update = SliceUpdate::Redraw;
  std::string_view redraw = "off";
  std::string_view deferred;  // staggered: the change to a held caster let stand this frame ("" when none)
};

struct FrameStats {
  // Per pass (kFramePassNames). The blur's: both halves at half resolution; at full resolution its
  // horizontal pass, its vertical pass being part of the lighting's.
  PassTimes passMs;
  int visibleObjects = 0;
  int hiddenByReprojection = 0;  // trees and props that showed in the last image, guessed hidden now ([culling] image_reprojection)
  int casterObjects = 0;
  // Visible objects whose boxes selected casters: with the read-back's record, those with pixels
  // in it (ShadowSetupPass::startPlan); else every visible object.
  int casterReceivers = 0;
  long long geometryTriangles = 0;
  long long shadowTriangles = 0;
  long long shadowTerrainTriangles = 0;  // of shadowTriangles: terrain (by block, Terrain::blockMayFaceAway)
  double farDepth = 0.0;        // z_f of the visible set
  bool sunBelowHorizon = false;
  double impostorDistance = 0.0;  // beyond it (m, over the size class's scale) trees were impostors; 0: none
  shadows::ShadowDiagnostics shadow;  // slice 0's
  int cascades = 1;                   // slices used (1: one map)
  double splitLambda = 0.0, cascadeBlend = 0.0;
  double nearestDepth = 0.0;          // z_near the splits started from (m; the camera's near until the depth buffer's is known)
  std::array<CascadeStats, shadows::kMaxCascades> cascade{};
  culling::CullingStats culling;
  // chc++ was asked and frustum culling drew the frame, its queries found not to pay ([culling]
  // query_payoff, culling::QueryPayoff; with the read-back, CasterSelection::ReceiverPixels, and
  // Profiling timing); the visible set then is the read-back's objects with pixels.
  bool culledByFrustum = false;
  // This frame's number (0, 1, … since the Frame was made). The pass times above are this frame's in
  // Profiling mode; with GpuQueries they are 0 and passTimesPending is set: they come later from
  // Frame::takePassTimes under this number.
  std::uint64_t frameNumber = 0;
  bool passTimesPending = false;

  // Takes the pass times of a gl::FrameTiming whose passes carry kFramePassNames.
  void setPassTimes(const gl::FrameTiming& timing);
};

// The floors of the full-screen passes at this frame's size (Frame::timePassFloors): passes that
// only read what the real ones read and write a colour, ms.
struct PassFloorTimes {
  double emptyMs = 0.0;           // no reads: a constant colour
  double gbufferMs = 0.0;         // the G-buffer's surface texel (the lighting's reads with the term looked up)
  double gbufferAndTermMs = 0.0;  // that and a gather of the half-resolution term (the lighting's with the upsample)
  double gbufferBlocksMs = 0.0;   // at half resolution, a 2 × 2 block's depths and one texel (the half-resolution term's)
  double termTapsMs = 0.0;        // at half resolution, three texels of the term (one half of the blur's, one tap each side)
  double gbufferBlocksAndMapMs = 0.0;  // the blocks' reads and one PCF lookup of the shadow map (the half-resolution term's)
  double gbufferAndMapMs = 0.0;        // the surface texel and one PCF lookup (the lighting's where it looks the term up)
};

class PassFloors;  // src/pass_floors.hpp

// One step of building a frame's scene (Frame::Frame), in order: `terrain` (heights, normals,
// tiles), `trees` (the species' meshes and LOD chains, placement, clusters), `objects` (every
// object's box and query shapes), `gpu_upload` (the passes' buffers, textures and programs),
// `bvh` (the culling hierarchy): its wall time, the process's resident memory and its heap in use
// after it (core/heap.hpp; on a software renderer the GPU's buffers are heap too).
struct StartupStep {
  const char* name;
  double ms = 0.0;
  double rssMib = 0.0;
  double heapMib = 0.0;
};

class Frame {
 public:
  // Generates the scene's terrain and forest and uploads everything (needs a current GL context).
  Frame(const Scene& scene, int width, int height);
  ~Frame();

  FrameStats render(const Camera& camera, double time, const FrameSettings& settings);
  // GpuQueries timing: the pass times of earlier frames whose queries have finished (oldest first,
  // each once; FrameTiming::frame is FrameStats::frameNumber). Never waits. Empty in Profiling mode.
  std::vector<gl::FrameTiming> takePassTimes();
  // The same, waiting for every frame still in flight: at the end of a run.
  std::vector<gl::FrameTiming> drainPassTimes();
  // Dynamic scenes: moves trees (bases snapped to the terrain), or takes the scene's props again
  // after the caller moved them (core moveProps on the Scene the frame was built from); both
  // update the object boxes and refit the culling BVH (rebuilt past kRebuildCostRatio).
  void moveTrees(std::span<const vegetation::Forest::Move> moves);
  void propsMoved();

  // Exactness checks: the geometry pass alone, with frustum culling on a culler of its own, so that
  // none of the frame-to-frame state (CHC history, smoothed n, stable radius, frozen set) changes;
  // readObjectIds and readDepth then return its G-buffer.
  void renderReferenceGeometry(const Camera& camera, double time);

  // Forgets the frame-to-frame state — CHC visibility, the smoothed n, the stable map's radius, a
  // frozen visible set — as
  // after a camera cut.
  void resetHistory();

  // The full-screen passes' floors on the last frame's G-buffer, each the median of `repeats`
  // runs timed with glFinish (render/src/pass_floors.hpp; its programs compile on the first call).
  PassFloorTimes timePassFloors(int repeats);

  Image8 readColor() const;                       // top row first
  // Copies the lit image into a framebuffer of that size (0: a window's back buffer).
  void presentTo(GLuint framebuffer, int width, int height) const;
  // Bottom row first (GL), 1 lit, 0 shadowed; before the blur. With the term at half resolution
  // (shadowTermScale 2) each pixel holds the term of its 2 × 2 block.
  std::vector<float> readShadowTerm() const;
  std::vector<float> readBlurredShadowTerm() const;  // what lighting used (= the term when the blur is off)
  // Both throw forest::Error where the last frame did not keep the term they read (keepShadowTerm).
  std::vector<std::uint32_t> readObjectIds() const;  // bottom row first, 0 = sky
  std::vector<float> readDepth() const;           // bottom row first, reversed-Z
  // What the last frame recorded as showing ([culling] image_visibility; the next frame's culling
  // reads it; from the G-buffer's read-back with CasterSelection::ReceiverPixels, else from the
  // lighting pass): per object, 1 where it had a pixel; per terrain tile, bit b where its block b
  // of the 4 × 4 at levels 0–3 had one. Waits for the lighting pass where that records; the next
  // frame then culls without the record. Throws forest::Error where no record is pending.
  struct ShownInImage {
    std::vector<std::uint8_t> objects;
    std::vector<std::uint16_t> blocks;
  };
  ShownInImage readShownInImage();
  // The last shadow map (of slice `slice`): depth in [0, 1] (0 nearest the light), size × size
  // for the slice's shadowMapSize(slice), bottom row first.
  std::vector<float> readShadowMap(int slice = 0) const;
  int shadowMapSize(int slice = 0) const;  // the last frame's layer of the slice, texels per side

  int width() const { return width_; }
  int height() const { return height_; }
  const std::vector<StartupStep>& startupSteps() const { return startup_; }
  const SceneObjects& objects() const { return *objects_; }
  const terrain::Terrain* terrain() const { return terrain_.get(); }
  const vegetation::Forest* forest() const { return forest_.get(); }
  // The last frame's slices (1 without cascades) and the slice whose layer a pixel at eye depth z
  // reads (in the blend band the nearer slice is mixed in too).
  int cascadeCount() const;
  int cascadeOf(double eyeDepth) const;
  // The last frame's shadow setup of a slice (tests compare against it).
  const shadows::ShadowSetup& shadowSetup(int slice = 0) const;
  // The last frame's visible set, a slice's casters (object indices, increasing: those its layer
  // drew — with CasterSelection::ReceiverMaskGpu the trees the GPU kept, read back, so this waits
  // for the shadow pass) and the camera it was built from (near and far: the slice's ends; one map:
  // far = the visible set's z_f) — for debug views and the truth.
  const std::vector<std::uint32_t>& visibleObjects() const;
  std::vector<std::uint32_t> casters(int slice = 0) const;
  const Camera& shadowCamera(int slice = 0) const;
  // The scene's start camera for this image (camera.above_ground applied).
  Camera startCamera() const;
  // The start camera moved to a camera path's pose; `aboveGround`: the pose's height is over the
  // terrain (CameraPath::aboveGround).
  Camera cameraAt(const CameraPose& pose, bool aboveGround) const;

 private:
  void requireUsedTerm(const char* reader) const;
  // Bakes them at the first frame that asks; the switch distance resolved for the camera.
  double useImpostors(const FrameSettings& settings, const Camera& camera);
  void objectsMoved();  // after object boxes changed: refit the BVH, recompute the scene bounds
  std::optional<terrain::TerrainLod> terrainLodFor(const Camera& camera) const;  // none without terrain
  struct Passes;  // the passes in order (src/*_pass.hpp) and what a frame tells the next (src/frame_history.hpp)
  struct Inputs;  // what a frame is drawn with, resolved at its start
  // The stages of render(), in order.
  Inputs resolveInputs(const Camera& camera, double time, const FrameSettings& settings) const;
  FrameStats beginFrame(const Inputs& in);
  const culling::CullingResult& drawGeometry(const Inputs& in, FrameStats& stats);
  const culling::CullingResult& setUpShadows(const Inputs& in, const culling::CullingResult& culled, FrameStats& stats);
  const gl::Texture* shadowTerm(const Inputs& in);  // the blurred term lighting reads; null with the blur off
  void endFrame(const Inputs& in, const culling::CullingResult& visible, FrameStats& stats);
  static std::string passName(FramePass pass);
  const struct ShadowSlice& slice(int index) const;  // throws InputError past the last frame's slices
  const Scene& scene_;
  int width_, height_;
  std::vector<StartupStep> startup_;
  std::unique_ptr<terrain::Terrain> terrain_;
  std::unique_ptr<vegetation::Forest> forest_;
  std::unique_ptr<SceneObjects> objects_;
  std::unique_ptr<Passes> passes_;
  std::unique_ptr<PassFloors> floors_;  // made by the first timePassFloors
  culling::Bvh bvh_;
  culling::OcclusionCuller culler_;
  std::unique_ptr<culling::OcclusionCuller> referenceCuller_;  // renderReferenceGeometry's, built on first use
  Aabb sceneBounds_;
  bool termWritten_ = false;  // the last frame's shadow term pass ran (the blur on)
  bool wholeShadowMap_ = true;  // the last frame's shadow pass drew every texel (FrameSettings::wholeShadowMap)
  bool usedTermKept_ = false;  // the last frame's lighting pass wrote the term it used (keepShadowTerm)
  std::unique_ptr<gl::PassTimer> timer_;  // made for the mode of the first frame, remade on a change
  gl::FrameTiming passTiming_;            // profiling: this frame's pass times, read back (storage reused)
  std::uint64_t framesRendered_ = 0;
};

}  // namespace forest::render
