#pragma once
// The scene file: one TOML document that declares everything a run needs and nothing more
// ("model only what a scene needs"). Schema and examples: docs/scene-format.md.
// Unknown keys, wrong types and out-of-range values are rejected with file:line:column, the key,
// the value and what was expected (InputError).
#include <glm/glm.hpp>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "forest/core/camera.hpp"

namespace forest {

// [camera]: the eye's optics and its start pose (a path file overrides the pose).
struct CameraSettings {
  glm::dvec3 position{0.0, 2.0, 10.0};
  double yaw_deg = 0.0;    // 0 looks along −z, positive turns left
  double pitch_deg = 0.0;  // [−90, 90]
  double fovy_deg = 60.0;  // (0, 180)
  double near = 0.1;       // > 0
  double far = 70.0;       // > near
  // When set (and the scene has terrain), position.y is replaced by the ground height under the
  // camera plus this many metres: a walker's eye needs no knowledge of the generated heights.
  std::optional<double> above_ground;
};

// [sun]: a directional light.
struct SunSettings {
  glm::dvec3 direction{0.3, -0.8, 0.2};  // the way light travels (noon: (0, −1, 0)); unit after load
  glm::dvec3 color{1.0, 0.97, 0.9};      // linear RGB, each >= 0
  double ambient = 0.15;                 // weak global ambient (thesis §6.2), [0, 1]
};

// [render]: output image.
struct RenderSettings {
  int width = 1280;   // [1, 16384]
  int height = 720;   // [1, 16384]
  glm::dvec3 sky_color{0.55, 0.7, 0.9};  // the zenith's; the horizon is paler (lighting.frag)
  double haze = 0.0;                     // distance haze: exponential extinction per metre, [0, 1]; 0: none
};

// [shadows]: z-partitioning of the sun's shadow map (DESIGN §4; Zhang et al. 2006). The command
// line's --cascades / --split-lambda / --cascade-blend override these.
struct ShadowSettings {
  int cascades = 1;            // slices of the visible depth range, each with its own map layer, [1, 4]
  double split_lambda = 0.8;   // Zhang eq. (4): 1 logarithmic splits, 0 uniform, [0, 1]
  // Share of a split's distance beyond it over which the nearer slice fades into the farther one
  // (no visible seam), [0, 0.5]; 0: a hard switch.
  double cascade_blend = 0.1;
};

// [[props]]: simple solid objects (boxes) — test scenes, obstacles and moving objects.
struct PropBox {
  glm::dvec3 min{0.0};
  glm::dvec3 max{1.0};
  glm::dvec3 albedo{0.7};
};

// Moves props between frames (a dynamic scene): each move gives the prop's new min corner, its
// size is kept. Returns the indices of the props whose boxes changed, in increasing order; throws
// InputError for an index out of range.
struct PropMove {
  std::uint32_t prop;
  glm::dvec3 min;
};
std::vector<std::uint32_t> moveProps(std::vector<PropBox>& props, const std::vector<PropMove>& moves);

// [terrain]: the procedural ground (module terrain/). Absent = no terrain.
struct TerrainSettings {
  double size = 2000.0;          // metres per side, [64, 65536]; centred on the origin
  int samples = 1025;            // height samples per side, 65…8193, (samples − 1) a multiple of 64
  double height_min = 0.0;       // the heights fill [height_min, height_max] exactly
  double height_max = 150.0;     // > height_min
  double feature_size = 1000.0;  // metres, wavelength of the lowest noise octave, > 0
  int octaves = 7;               // [1, 16]
  double ridged = 0.4;           // share of ridged noise in the blend with fBm, [0, 1]
  std::uint64_t seed = 1;        // same seed → bit-identical heights
  double lod_error_pixels = 2.0; // screen-space error bound of the LOD, (0, 64] pixels
  glm::dvec3 albedo{0.32, 0.42, 0.2};  // grass; steep slopes blend to rock
};

// [vegetation.conifer] / [vegetation.broadleaf] / [vegetation.shrub]: where a species grows. A
// placed tree's species is drawn with weights share × (1 + altitude_bias (2a − 1)) ×
// (1 + slope_bias (2s − 1)) × (1 + shade_bias (2D − 1)) among the species whose hard rules (height
// band, slope) the site passes: a is the altitude in the terrain's height range, s the slope over
// 45° (at most 1), D the stand density (docs/scene-format.md). The biases are in [−1, 1]; 0 leaves
// the share alone.
struct SpeciesPlacementSettings {
  double share = 0.5;             // share of the trees, [0, 1] (the shares are normalised)
  double spacing = 4.0;           // metres, minimum distance to any other tree, [0.5, 100] (× the size class's scale)
  double max_slope_deg = 35.0;    // steepest ground it grows on, [0, 90]
  double min_height = -1e4;       // world height band of its bases
  double max_height = 1e4;
  double altitude_bias = 0.0;     // > 0: more of it higher up
  double slope_bias = 0.0;        // > 0: more of it on steep ground
  double shade_bias = 0.0;        // > 0: more of it inside stands (shade, moist floor); < 0: at edges and in clearings
};

// [vegetation.sizes]: size classes young, mature, old — their shares (normalised) and scale
// factors (× the per-tree scale). A young tree's LOD chain starts at LOD1 (a quarter of the LOD0
// budget), and every tree's LOD distance bands grow with its class's scale (LOD by size on screen).
enum class SizeClass { Young, Mature, Old };
constexpr int kSizeClassCount = 3;
struct SizeClassSettings {
  glm::dvec3 share{0.0, 1.0, 0.0};   // [0, 1] each, not all 0
  glm::dvec3 scale{0.45, 1.0, 1.35}; // (0, 4] each
};

// [vegetation.stands]: placement by a density field D (vegetation/stand_field.hpp,
// docs/scene-format.md) — stands with soft edges, clearings and meadows between them. Without it
// the trees are spread evenly.
struct StandSettings {
  double cover = 0.3;       // share of the terrain in stands (where D ≥ 1/2), [0.01, 0.95]
  double feature_m = 200.0; // typical size of a stand or a clearing, metres, [10, 5000]
  double edge = 0.15;       // softness of the stands' edges: the share of the noise range over which D
                            // ramps from the meadow's value to 1, [0.01, 1]
  double meadow = 0.02;     // D far from the stands (scattered trees; 0: none), [0, 1]
};

// [vegetation]: procedural trees on the terrain (module vegetation/; needs [terrain]).
// procedural: three OpenMesh species (conifer, broadleaf, shrub) with LOD chains (issue "Vegetation"); thesis: the "tree-like
// objects" of the thesis demo (ch. 10) — a closed cone and a closed torus ring around it.
enum class TreeStyle { Procedural, Thesis };

// [vegetation.trail]: a walkway kept free of trees — no tree whose branches reach, between 0.3 and
// 3 m above its base, within width / 2 of the polyline through `points` (x, z) is placed (a walk's
// camera along it keeps clear of trunks and crowns).
struct TrailSettings {
  std::vector<glm::dvec2> points;  // at least 2
  double width = 2.0;              // metres, (0, 20]
};

struct VegetationSettings {
  TreeStyle style = TreeStyle::Procedural;
  int count = 5000;               // trees requested, [0, 1000000]; fewer when they do not fit (reported)
  int grid = 0;                   // > 0: grid × grid trees on a jittered regular grid instead (count ignored)
  glm::dvec2 scale_range{0.8, 1.25};  // per-tree scale, uniform in [first, second] by the seed
  std::uint64_t seed = 1;         // placement, species shapes, instance variation
  int lod0_triangles = 2000;      // LOD0 budget per tree, [1000, 20000]; LOD1/LOD2 a quarter/sixteenth
  bool force_lod0 = false;        // every tree at LOD0 (stress runs)
  // Metres: LOD0 below the first, LOD1 below the second, LOD2 below the third, then LOD3. A file
  // may give two (no LOD3: the third is +∞).
  glm::dvec3 lod_distances{60.0, 180.0, 450.0};
  double wind_strength = 0.02;    // largest sway: horizontal shift per metre of height, [0, 0.2]
  double wind_period = 4.0;       // seconds, > 0
  glm::dvec2 wind_direction{1.0, 0.3};    // (x, z), non-zero; normalised on load
  SpeciesPlacementSettings conifer{0.6, 4.0, 35.0, -1e4, 1e4};
  SpeciesPlacementSettings broadleaf{0.4, 6.0, 25.0, -1e4, 1e4};
  SpeciesPlacementSettings shrub{0.0, 1.5, 40.0, -1e4, 1e4};  // understorey; none unless a share is given
  SizeClassSettings sizes;
  std::optional<StandSettings> stands;  // absent: trees spread evenly
  std::optional<TrailSettings> trail;   // absent: none
  // x0, z0, x1, z1 (x0 < x1, z0 < z1): the trees stand inside this rectangle (its part on the
  // terrain); absent: on the whole terrain. The stands' cover is of this area.
  std::optional<glm::dvec4> area;
};

// [culling]: parameters of the chc++ strategy (Mattausch, Bittner, Wimmer, EG 2008).
struct CullingSettings {
  // Objects per leaf of the culling hierarchy, [1, 64]: 1 decides visibility and shadow casters per
  // tree (the BVH's interior nodes group the trees); more trade drawn triangles for fewer queries,
  // which pays where a query is dear (a software renderer flushes its pipeline on each result).
  int leaf_size = 1;
  // Previously invisible nodes queued before their queries are issued, [1, 1000]. The paper's 50
  // suits a GPU that answers while the CPU goes on; on llvmpipe each result taken drains the whole
  // pipeline, and 200 halves chc++'s wait (bench culling, 50 000 trees, ground path).
  int batch_size = 200;
  int visible_requery_frames = 8;   // n_av: a visible leaf is queried again every n_av frames, [1, 100]
  bool multiqueries = true;         // one query for a group of nodes likely to stay invisible
  int tight_box_depth = 3;          // query a node with its descendants' boxes down to this depth, [0, 8] (0: own box)
  double tight_box_area_ratio = 1.4;  // ... when their total area is at most this × the node's box area, [0.1, 10]
  // A leaf whose box query found it visible is queried once more with its trees' own triangles
  // before it is drawn, and visible leaves are re-queried so (a box sees through the gaps between
  // nearer crowns): fewer trees drawn, for queries that draw the candidates' triangles depth-tested only.
  bool geometry_queries = true;
  // A drawn tile's terrain blocks are drawn only while visible: the others are queried after the
  // traversal, with its last batch of queries (render::TerrainBlockVisibility; no wait of their
  // own), and those found visible drawn then; strategies without chc++'s end-of-frame
  // confirmation ask their visible set again after them (OcclusionCuller::refineVisibleSet).
  // false: a drawn tile draws every block in the frustum.
  bool terrain_blocks = true;
  // chc++ reads which objects and terrain blocks had a pixel in the frame before (recorded from the
  // G-buffer's IDs by the lighting pass, or from the receiver mask's read-back of them:
  // render/src/image_visibility.hpp): a leaf or block
  // drawn then without one is asked before it is drawn again, one with a pixel needs no re-query.
  bool image_visibility = true;
  // With image_visibility taken from the read-back G-buffer (a software renderer): the last
  // image's surface points moved into the next view (culling::ReprojectedImage) say which trees
  // and props that showed are hidden now; those are asked before they are drawn again. Off by
  // default: along the default forest's walk it saved 3% of the eye triangles but asked 13% more
  // queries (+3–6 ms geometry pass on llvmpipe); on in the thesis demo's dense grid, where it
  // brings 10 201 trees from 1.23 to 1.19 of the visible set's triangles (docs/design.md).
  bool image_reprojection = false;
  // chc++ measures whether its queries pay (culling::QueryPayoff): where frustum culling's frames
  // are faster (an open view over a flat canopy on a software renderer), it draws by frustum
  // culling and probes the queries again now and then. Needs the record of what showed
  // (image_visibility from the read-back) to hand chc++ its state back after such frames, and the
  // frame timed by profile (glFinish and a clock): both the software renderer's defaults.
  bool query_payoff = true;
};

struct Scene {
  std::string source = "<built-in>";  // file the scene was read from
  CameraSettings camera;
  SunSettings sun;
  RenderSettings render;
  ShadowSettings shadows;
  std::vector<PropBox> props;
  std::optional<TerrainSettings> terrain;
  std::optional<VegetationSettings> vegetation;
  CullingSettings culling;

  // The eye camera at the scene's start pose, with the render aspect ratio.
  Camera startCamera() const;
};

// Reads and validates a scene file (throws InputError).
Scene loadScene(const std::filesystem::path& file);
// Parses scene text; `name` is used in error messages.
Scene parseScene(const std::string& text, const std::string& name);
// Serialises to TOML that parseScene reads back to an equal scene.
std::string sceneToToml(const Scene& scene);

}  // namespace forest
