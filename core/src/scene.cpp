#include "forest/core/scene.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <sstream>

#include "forest/core/camera_path.hpp"
#include "forest/core/error.hpp"
#include "forest/core/files.hpp"
#include "toml_schema.hpp"

namespace forest {
using detail::TomlSection;

namespace {

constexpr int kMaxImageSide = 16384;  // larger targets are refused before allocating

void readCamera(TomlSection& s, CameraSettings& c) {
  c.position = s.vec3("position", c.position, detail::anyFinite());
  c.yaw_deg = s.number("yaw_deg", c.yaw_deg, detail::anyFinite());
  c.pitch_deg = s.number("pitch_deg", c.pitch_deg, detail::closed(-90.0, 90.0));
  c.fovy_deg = s.number("fovy_deg", c.fovy_deg, detail::open(0.0, 180.0));
  c.near = s.number("near", c.near, detail::positive());
  c.far = s.number("far", c.far, detail::positive());
  if (!(c.far > c.near)) {
    s.fail(nullptr, "far", "must be greater than camera.near = " + std::to_string(c.near));
  }
  if (s.has("above_ground")) c.above_ground = s.number("above_ground", std::nullopt, detail::closed(0.0, 1e4));
  s.finish();
}

void readSun(TomlSection& s, SunSettings& sun) {
  sun.direction = s.vec3("direction", sun.direction, detail::anyFinite());
  const double length = glm::length(sun.direction);
  if (!(length > 1e-12) || !std::isfinite(length)) {
    s.fail(nullptr, "direction", "must be a non-zero vector (the way sunlight travels)");
  }
  // Normalised unless already unit to double precision, so a saved scene reads back bit-exact.
  if (std::abs(length - 1.0) > 4.0 * std::numeric_limits<double>::epsilon()) sun.direction /= length;
  sun.color = s.vec3("color", sun.color, detail::nonNegative());
  sun.ambient = s.number("ambient", sun.ambient, detail::closed(0.0, 1.0));
  s.finish();
}

void readRender(TomlSection& s, RenderSettings& r) {
  r.width = static_cast<int>(s.integer("width", r.width, 1, kMaxImageSide));
  r.height = static_cast<int>(s.integer("height", r.height, 1, kMaxImageSide));
  r.sky_color = s.vec3("sky_color", r.sky_color, detail::closed(0.0, 1.0));
  r.haze = s.number("haze", r.haze, detail::closed(0.0, 1.0));
  s.finish();
}

void readShadows(TomlSection& s, ShadowSettings& sh) {
  sh.cascades = static_cast<int>(s.integer("cascades", sh.cascades, 1, 4));
  sh.split_lambda = s.number("split_lambda", sh.split_lambda, detail::closed(0.0, 1.0));
  sh.cascade_blend = s.number("cascade_blend", sh.cascade_blend, detail::closed(0.0, 0.5));
  s.finish();
}

void readCulling(TomlSection& s, CullingSettings& c) {
  c.leaf_size = static_cast<int>(s.integer("leaf_size", c.leaf_size, 1, 64));
  c.batch_size = static_cast<int>(s.integer("batch_size", c.batch_size, 1, 1000));
  c.visible_requery_frames = static_cast<int>(s.integer("visible_requery_frames", c.visible_requery_frames, 1, 100));
  c.multiqueries = s.boolean("multiqueries", c.multiqueries);
  c.tight_box_depth = static_cast<int>(s.integer("tight_box_depth", c.tight_box_depth, 0, 8));
  c.tight_box_area_ratio = s.number("tight_box_area_ratio", c.tight_box_area_ratio, detail::closed(0.1, 10.0));
  c.geometry_queries = s.boolean("geometry_queries", c.geometry_queries);
  c.terrain_blocks = s.boolean("terrain_blocks", c.terrain_blocks);
  c.image_visibility = s.boolean("image_visibility", c.image_visibility);
  c.image_reprojection = s.boolean("image_reprojection", c.image_reprojection);
  c.query_payoff = s.boolean("query_payoff", c.query_payoff);
  s.finish();
}

PropBox readProp(TomlSection& s) {
  s.oneOf("shape", "box", {"box"});
  PropBox box;
  box.min = s.vec3("min", std::nullopt, detail::anyFinite());
  box.max = s.vec3("max", std::nullopt, detail::anyFinite());
  for (int i = 0; i < 3; ++i) {
    if (!(box.max[i] > box.min[i])) s.fail(nullptr, "max", "must be greater than min on every axis");
  }
  box.albedo = s.vec3("albedo", box.albedo, detail::closed(0.0, 1.0));
  s.finish();
  return box;
}

void readTerrain(TomlSection& s, TerrainSettings& t) {
  t.size = s.number("size", t.size, detail::closed(64.0, 65536.0));
  t.samples = static_cast<int>(s.integer("samples", t.samples, 65, 8193));
  if ((t.samples - 1) % 64 != 0) s.fail(nullptr, "samples", "samples - 1 must be a multiple of 64 (tiles of 64 quads), e.g. 1025");
  t.height_min = s.number("height_min", t.height_min, detail::closed(-1e4, 1e4));
  t.height_max = s.number("height_max", t.height_max, detail::closed(-1e4, 1e4));
  if (!(t.height_max > t.height_min)) s.fail(nullptr, "height_max", "must be greater than terrain.height_min");
  t.feature_size = s.number("feature_size", t.feature_size, detail::positive());
  t.octaves = static_cast<int>(s.integer("octaves", t.octaves, 1, 16));
  t.ridged = s.number("ridged", t.ridged, detail::closed(0.0, 1.0));
  t.seed = static_cast<std::uint64_t>(
      s.integer("seed", static_cast<std::int64_t>(t.seed), 0, std::numeric_limits<std::int64_t>::max()));
  t.lod_error_pixels = s.number("lod_error_pixels", t.lod_error_pixels, detail::NumberRange{0.0, 64.0, true, false});
  t.albedo = s.vec3("albedo", t.albedo, detail::closed(0.0, 1.0));
  s.finish();
}

void readSpeciesPlacement(TomlSection& s, SpeciesPlacementSettings& p) {
  p.share = s.number("share", p.share, detail::closed(0.0, 1.0));
  p.spacing = s.number("spacing", p.spacing, detail::closed(0.5, 100.0));
  p.max_slope_deg = s.number("max_slope_deg", p.max_slope_deg, detail::closed(0.0, 90.0));
  p.min_height = s.number("min_height", p.min_height, detail::closed(-1e4, 1e4));
  p.max_height = s.number("max_height", p.max_height, detail::closed(-1e4, 1e4));
  if (!(p.max_height >= p.min_height)) s.fail(nullptr, "max_height", "must be at least min_height");
  p.altitude_bias = s.number("altitude_bias", p.altitude_bias, detail::closed(-1.0, 1.0));
  p.slope_bias = s.number("slope_bias", p.slope_bias, detail::closed(-1.0, 1.0));
  p.shade_bias = s.number("shade_bias", p.shade_bias, detail::closed(-1.0, 1.0));
  s.finish();
}

void readSizes(TomlSection& s, SizeClassSettings& t) {
  t.share = s.vec3("share", t.share, detail::closed(0.0, 1.0));
  if (!(t.share.x + t.share.y + t.share.z > 0.0)) s.fail(nullptr, "share", "the size classes' shares must not all be 0");
  t.scale = s.vec3("scale", t.scale, detail::closed(1e-3, 4.0));
  s.finish();
}

void readStands(TomlSection& s, StandSettings& t) {
  t.cover = s.number("cover", t.cover, detail::closed(0.01, 0.95));
  t.feature_m = s.number("feature_m", t.feature_m, detail::closed(10.0, 5000.0));
  t.edge = s.number("edge", t.edge, detail::closed(0.01, 1.0));
  t.meadow = s.number("meadow", t.meadow, detail::closed(0.0, 1.0));
  s.finish();
}

// [vegetation.trail] path: the camera path's position every kTrailStep seconds and at its end,
// the path file relative to the scene file's folder.
std::vector<glm::dvec2> trailAlongPath(TomlSection& t, const std::string& pathFile) {
  constexpr double kTrailStep = 0.5;
  const std::filesystem::path file = std::filesystem::path(t.file()).parent_path() / pathFile;
  if (!std::filesystem::is_regular_file(file))
    t.fail(nullptr, "path", fmt::format("no camera-path file {} (the path is relative to the scene file's folder)", file.string()));
  const CameraPath path = CameraPath::load(file);
  std::vector<glm::dvec2> points;
  for (double time = path.startTime(); time < path.endTime() + kTrailStep; time += kTrailStep) {
    const glm::dvec3 p = path.at(std::min(time, path.endTime())).position;
    points.emplace_back(p.x, p.z);
  }
  if (points.size() < 2) points.push_back(points.front() + glm::dvec2(1e-3, 0.0));  // a one-key path: a point-like trail
  return points;
}

void readVegetation(TomlSection& s, VegetationSettings& v) {
  v.style = s.oneOf("style", std::string("procedural"), {"procedural", "thesis"}) == "thesis" ? TreeStyle::Thesis : TreeStyle::Procedural;
  v.count = static_cast<int>(s.integer("count", v.count, 0, 1000000));
  v.grid = static_cast<int>(s.integer("grid", v.grid, 0, 1000));
  v.scale_range = s.vec2("scale_range", v.scale_range, detail::positive());
  if (!(v.scale_range.y >= v.scale_range.x)) s.fail(nullptr, "scale_range", "the second scale must not be smaller than the first");
  v.seed = static_cast<std::uint64_t>(
      s.integer("seed", static_cast<std::int64_t>(v.seed), 0, std::numeric_limits<std::int64_t>::max()));
  v.lod0_triangles = static_cast<int>(s.integer("lod0_triangles", v.lod0_triangles, 1000, 20000));
  v.force_lod0 = s.boolean("force_lod0", v.force_lod0);
  if (s.arraySize("lod_distances") == 2) {
    v.lod_distances = glm::dvec3(s.vec2("lod_distances", std::nullopt, detail::positive()), std::numeric_limits<double>::infinity());
  } else {
    v.lod_distances = s.vec3("lod_distances", v.lod_distances, detail::positive());
  }
  if (!(v.lod_distances.y > v.lod_distances.x && v.lod_distances.z > v.lod_distances.y))
    s.fail(nullptr, "lod_distances", "each distance must be greater than the one before");
  v.wind_strength = s.number("wind_strength", v.wind_strength, detail::closed(0.0, 0.2));
  v.wind_period = s.number("wind_period", v.wind_period, detail::positive());
  v.wind_direction = s.vec2("wind_direction", v.wind_direction, detail::anyFinite());
  if (!(glm::length(v.wind_direction) > 1e-9)) s.fail(nullptr, "wind_direction", "must be a non-zero (x, z) vector");
  const double windLength = glm::length(v.wind_direction);  // normalised unless already unit (round trips)
  if (std::abs(windLength - 1.0) > 4.0 * std::numeric_limits<double>::epsilon()) v.wind_direction /= windLength;
  if (auto t = s.table("conifer")) readSpeciesPlacement(*t, v.conifer);
  if (auto t = s.table("broadleaf")) readSpeciesPlacement(*t, v.broadleaf);
  if (auto t = s.table("shrub")) readSpeciesPlacement(*t, v.shrub);
  if (auto t = s.table("sizes")) readSizes(*t, v.sizes);
  if (auto t = s.table("stands")) readStands(*t, v.stands.emplace());
  if (auto t = s.table("trail")) {
    TrailSettings& trail = v.trail.emplace();
    if (const std::optional<std::string> path = t->text("path")) {
      if (t->has("points")) t->fail(nullptr, "points", "give the trail's points or its path, not both");
      trail.points = trailAlongPath(*t, *path);
    } else {
      const std::vector<double> xz = t->numberList("points", 4, detail::anyFinite());
      if (xz.size() % 2 != 0) t->fail(nullptr, "points", "expected x, z pairs: an even count of numbers");
      for (size_t i = 0; i + 1 < xz.size(); i += 2) trail.points.emplace_back(xz[i], xz[i + 1]);
    }
    trail.width = t->number("width", trail.width, detail::closed(1e-3, 20.0));
    t->finish();
  }
  if (s.has("area")) {
    const std::vector<double> a = s.numberList("area", 4, detail::anyFinite());
    if (a.size() != 4 || !(a[0] < a[2]) || !(a[1] < a[3]))
      s.fail(nullptr, "area", "expected [x0, z0, x1, z1] with x0 < x1 and z0 < z1 (metres)");
    v.area = glm::dvec4(a[0], a[1], a[2], a[3]);
  }
  if (v.stands && v.grid > 0) s.fail(nullptr, "grid", "a grid places trees evenly; leave it out (or 0) with [vegetation.stands]");
  if (!(v.conifer.share + v.broadleaf.share + v.shrub.share > 0.0)) s.fail(nullptr, "conifer.share", "the species shares must not all be 0");
  s.finish();
}

}  // namespace

std::vector<std::uint32_t> moveProps(std::vector<PropBox>& props, const std::vector<PropMove>& moves) {
  std::vector<std::uint32_t> changed;
  for (const PropMove& move : moves) {
    if (move.prop >= props.size())
      throw InputError("moveProps: no prop " + std::to_string(move.prop) + " (the scene has " + std::to_string(props.size()) + ")");
    PropBox& p = props[move.prop];
    if (p.min == move.min) continue;
    const glm::dvec3 size = p.max - p.min;
    p.min = move.min;
    p.max = move.min + size;
    changed.push_back(move.prop);
  }
  std::sort(changed.begin(), changed.end());
  changed.erase(std::unique(changed.begin(), changed.end()), changed.end());
  return changed;
}

Camera Scene::startCamera() const {
  Camera c;
  c.position = camera.position;
  c.yaw = glm::radians(camera.yaw_deg);
  c.pitch = glm::radians(camera.pitch_deg);
  c.fovy = glm::radians(camera.fovy_deg);
  c.aspect = static_cast<double>(render.width) / render.height;
  c.near = camera.near;
  c.far = camera.far;
  return c;
}

Scene parseScene(const std::string& text, const std::string& name) {
  const toml::table document = detail::parseToml(text, name);
  TomlSection root(document, name, "");
  Scene scene;
  scene.source = name;
  if (auto s = root.table("camera")) readCamera(*s, scene.camera);
  if (auto s = root.table("sun")) readSun(*s, scene.sun);
  if (auto s = root.table("render")) readRender(*s, scene.render);
  if (auto s = root.table("shadows")) readShadows(*s, scene.shadows);
  if (auto s = root.table("culling")) readCulling(*s, scene.culling);
  for (auto& s : root.tables("props")) scene.props.push_back(readProp(s));
  if (auto s = root.table("terrain")) readTerrain(*s, scene.terrain.emplace());
  if (scene.camera.above_ground && !scene.terrain)
    throw InputError(name + ": camera.above_ground: needs a [terrain] section to stand on");
  if (auto s = root.table("vegetation")) {
    readVegetation(*s, scene.vegetation.emplace());
    if (!scene.terrain) s->failSection("needs a [terrain] section to grow on");
  }
  root.finish();
  return scene;
}

Scene loadScene(const std::filesystem::path& file) {
  return parseScene(readTextFile(file), file.string());
}

std::string sceneToToml(const Scene& scene) {
  using detail::tomlArray;
  toml::table camera{{"position", tomlArray(scene.camera.position)},
                     {"yaw_deg", scene.camera.yaw_deg},
                     {"pitch_deg", scene.camera.pitch_deg},
                     {"fovy_deg", scene.camera.fovy_deg},
                     {"near", scene.camera.near},
                     {"far", scene.camera.far}};
  if (scene.camera.above_ground) camera.insert("above_ground", *scene.camera.above_ground);
  toml::table sun{{"direction", tomlArray(scene.sun.direction)},
                  {"color", tomlArray(scene.sun.color)},
                  {"ambient", scene.sun.ambient}};
  toml::table render{{"width", scene.render.width},
                     {"height", scene.render.height},
                     {"sky_color", tomlArray(scene.render.sky_color)},
                     {"haze", scene.render.haze}};
  toml::array props;
  for (const PropBox& p : scene.props) {
    props.push_back(toml::table{{"shape", "box"},
                                {"min", tomlArray(p.min)},
                                {"max", tomlArray(p.max)},
                                {"albedo", tomlArray(p.albedo)}});
  }
  const CullingSettings& c = scene.culling;
  toml::table culling{{"leaf_size", c.leaf_size},
                      {"batch_size", c.batch_size},
                      {"visible_requery_frames", c.visible_requery_frames},
                      {"multiqueries", c.multiqueries},
                      {"tight_box_depth", c.tight_box_depth},
                      {"tight_box_area_ratio", c.tight_box_area_ratio},
                      {"geometry_queries", c.geometry_queries},
                      {"terrain_blocks", c.terrain_blocks},
                      {"image_visibility", c.image_visibility},
                      {"image_reprojection", c.image_reprojection},
                      {"query_payoff", c.query_payoff}};
  toml::table shadows{{"cascades", scene.shadows.cascades},
                      {"split_lambda", scene.shadows.split_lambda},
                      {"cascade_blend", scene.shadows.cascade_blend}};
  toml::table document{{"camera", camera}, {"sun", sun}, {"render", render}, {"shadows", shadows}, {"culling", culling}};
  if (!props.empty()) document.insert("props", props);
  if (scene.terrain) {
    const TerrainSettings& t = *scene.terrain;
    document.insert("terrain", toml::table{{"size", t.size},
                                           {"samples", t.samples},
                                           {"height_min", t.height_min},
                                           {"height_max", t.height_max},
                                           {"feature_size", t.feature_size},
                                           {"octaves", t.octaves},
                                           {"ridged", t.ridged},
                                           {"seed", static_cast<std::int64_t>(t.seed)},
                                           {"lod_error_pixels", t.lod_error_pixels},
                                           {"albedo", tomlArray(t.albedo)}});
  }
  if (scene.vegetation) {
    const VegetationSettings& v = *scene.vegetation;
    auto species = [](const SpeciesPlacementSettings& p) {
      return toml::table{{"share", p.share},
                         {"spacing", p.spacing},
                         {"max_slope_deg", p.max_slope_deg},
                         {"min_height", p.min_height},
                         {"max_height", p.max_height},
                         {"altitude_bias", p.altitude_bias},
                         {"slope_bias", p.slope_bias},
                         {"shade_bias", p.shade_bias}};
    };
    toml::table vegetation{{"style", v.style == TreeStyle::Thesis ? "thesis" : "procedural"},
                           {"count", v.count},
                           {"grid", v.grid},
                           {"scale_range", tomlArray(v.scale_range)},
                           {"seed", static_cast<std::int64_t>(v.seed)},
                           {"lod0_triangles", v.lod0_triangles},
                           {"force_lod0", v.force_lod0},
                           {"lod_distances", std::isinf(v.lod_distances.z) ? tomlArray(glm::dvec2(v.lod_distances))
                                                                           : tomlArray(v.lod_distances)},
                           {"wind_strength", v.wind_strength},
                           {"wind_period", v.wind_period},
                           {"wind_direction", tomlArray(v.wind_direction)},
                           {"conifer", species(v.conifer)},
                           {"broadleaf", species(v.broadleaf)},
                           {"shrub", species(v.shrub)},
                           {"sizes", toml::table{{"share", tomlArray(v.sizes.share)}, {"scale", tomlArray(v.sizes.scale)}}}};
    if (v.area) vegetation.insert("area", toml::array{v.area->x, v.area->y, v.area->z, v.area->w});
    if (v.stands)
      vegetation.insert("stands", toml::table{{"cover", v.stands->cover},
                                              {"feature_m", v.stands->feature_m},
                                              {"edge", v.stands->edge},
                                              {"meadow", v.stands->meadow}});
    if (v.trail) {
      toml::array points;
      for (const glm::dvec2& p : v.trail->points) {
        points.push_back(p.x);
        points.push_back(p.y);
      }
      vegetation.insert("trail", toml::table{{"points", std::move(points)}, {"width", v.trail->width}});
    }
    document.insert("vegetation", std::move(vegetation));
  }
  std::ostringstream out;
  out << document << "\n";
  return out.str();
}

}  // namespace forest
