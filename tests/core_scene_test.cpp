// Scene files: a valid file round-trips; every kind of bad input gives one line naming the file,
// the key (with line:column) and what was expected.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "forest/core/error.hpp"
#include "forest/core/scene.hpp"
#include "test_paths.hpp"

namespace forest {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

std::string errorOf(const std::string& text) {
  try {
    parseScene(text, "bad.toml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "<no error>";
}

TEST(SceneFile, RepositorySceneLoadsWithItsValues) {
  const Scene scene = loadScene(std::string(FOREST_REPO_DATA) + "/scenes/boxes.toml");
  EXPECT_EQ(scene.render.width, 640);
  EXPECT_EQ(scene.render.height, 360);
  EXPECT_DOUBLE_EQ(scene.camera.pitch_deg, -12.0);
  ASSERT_EQ(scene.props.size(), 4u);
  EXPECT_DOUBLE_EQ(scene.props[2].max.y, 5.0);
  EXPECT_NEAR(glm::length(scene.sun.direction), 1.0, 1e-15);  // normalised on load
}

TEST(SceneFile, RoundTripsThroughToml) {
  Scene scene = loadScene(std::string(FOREST_REPO_DATA) + "/scenes/boxes.toml");
  scene.camera.near = 0.123456789012345;  // needs all 17 digits to survive
  scene.camera.position = {1e6 + 0.1, -3.0, 1.0 / 3.0};
  scene.culling.batch_size = 17;
  scene.culling.leaf_size = 5;
  scene.culling.multiqueries = false;
  scene.culling.geometry_queries = false;
  scene.culling.terrain_blocks = false;  // not the default
  scene.culling.tight_box_area_ratio = 1.0 / 3.0;
  const Scene back = parseScene(sceneToToml(scene), "roundtrip.toml");
  EXPECT_EQ(back.culling.batch_size, 17);
  EXPECT_EQ(back.culling.leaf_size, 5);
  EXPECT_FALSE(back.culling.multiqueries);
  EXPECT_FALSE(back.culling.geometry_queries);
  EXPECT_FALSE(back.culling.terrain_blocks);
  EXPECT_EQ(back.culling.tight_box_area_ratio, scene.culling.tight_box_area_ratio);
  EXPECT_EQ(back.culling.visible_requery_frames, scene.culling.visible_requery_frames);
  EXPECT_EQ(back.camera.position, scene.camera.position);
  EXPECT_EQ(back.camera.near, scene.camera.near);
  EXPECT_EQ(back.camera.far, scene.camera.far);
  EXPECT_EQ(back.camera.fovy_deg, scene.camera.fovy_deg);
  EXPECT_EQ(back.camera.yaw_deg, scene.camera.yaw_deg);
  EXPECT_EQ(back.camera.pitch_deg, scene.camera.pitch_deg);
  EXPECT_EQ(back.sun.direction, scene.sun.direction);
  EXPECT_EQ(back.sun.color, scene.sun.color);
  EXPECT_EQ(back.sun.ambient, scene.sun.ambient);
  EXPECT_EQ(back.render.width, scene.render.width);
  EXPECT_EQ(back.render.sky_color, scene.render.sky_color);
  ASSERT_EQ(back.props.size(), scene.props.size());
  for (size_t i = 0; i < scene.props.size(); ++i) {
    EXPECT_EQ(back.props[i].min, scene.props[i].min);
    EXPECT_EQ(back.props[i].max, scene.props[i].max);
    EXPECT_EQ(back.props[i].albedo, scene.props[i].albedo);
  }
}

TEST(SceneFile, TerrainSectionLoadsAndRoundTrips) {
  Scene scene = loadScene(std::string(FOREST_REPO_DATA) + "/scenes/terrain.toml");
  ASSERT_TRUE(scene.terrain.has_value());
  EXPECT_EQ(scene.terrain->samples, 1025);
  EXPECT_DOUBLE_EQ(scene.terrain->size, 2000.0);
  scene.terrain->seed = 9007199254740993ull;  // above 2^53: must survive as an integer
  scene.terrain->ridged = 1.0 / 3.0;
  const Scene back = parseScene(sceneToToml(scene), "roundtrip.toml");
  ASSERT_TRUE(back.terrain.has_value());
  EXPECT_EQ(back.terrain->seed, scene.terrain->seed);
  EXPECT_EQ(back.terrain->ridged, scene.terrain->ridged);
  EXPECT_EQ(back.terrain->samples, scene.terrain->samples);
  EXPECT_EQ(back.terrain->albedo, scene.terrain->albedo);
  EXPECT_FALSE(parseScene("", "empty.toml").terrain.has_value());  // no section, no terrain
}

TEST(SceneFile, BadCullingValuesNameTheKey) {
  EXPECT_THAT(errorOf("[vegetation.trail]\npoints = [1.0, 2.0, 3.0]\n"), HasSubstr("expected an array of at least 4 numbers"));
  EXPECT_THAT(errorOf("[vegetation.trail]\npoints = [1.0, 2.0, 3.0, 4.0, 5.0]\n"), HasSubstr("expected x, z pairs"));
  EXPECT_THAT(errorOf("[vegetation.trail]\npoints = [1.0, 2.0, 3.0, 4.0]\nwidth = 0.0\n"), HasSubstr("vegetation.trail.width = 0"));
  {
    const Scene trail = parseScene("[terrain]\n[vegetation]\n[vegetation.trail]\npoints = [1.0, 2.0, 3.0, 4.5]\nwidth = 3.0\n", "t.toml");
    ASSERT_TRUE(trail.vegetation && trail.vegetation->trail);
    ASSERT_EQ(trail.vegetation->trail->points.size(), 2u);
    EXPECT_EQ(trail.vegetation->trail->points[1], glm::dvec2(3.0, 4.5));
    EXPECT_EQ(trail.vegetation->trail->width, 3.0);
    const Scene again = parseScene(sceneToToml(trail), "again.toml");  // the trail survives a round trip
    ASSERT_TRUE(again.vegetation->trail);
    EXPECT_EQ(again.vegetation->trail->points, trail.vegetation->trail->points);
  }
  EXPECT_THAT(errorOf("[culling]\nbatch_size = 0\n"), HasSubstr("culling.batch_size = 0: expected an integer in [1, 1000]"));
  EXPECT_THAT(errorOf("[culling]\nleaf_size = 65\n"), HasSubstr("culling.leaf_size = 65: expected an integer in [1, 64]"));
  EXPECT_THAT(errorOf("[culling]\nvisible_requery_frames = 101\n"), HasSubstr("culling.visible_requery_frames = 101"));
  EXPECT_THAT(errorOf("[culling]\ntight_box_area_ratio = nan\n"), HasSubstr("culling.tight_box_area_ratio = nan"));
  EXPECT_THAT(errorOf("[culling]\nmultiqueries = 1\n"), HasSubstr("culling.multiqueries = 1: expected true or false"));
  EXPECT_THAT(errorOf("[culling]\nbatch = 3\n"), HasSubstr("unknown key 'culling.batch'"));
}

// [vegetation.trail] path: the trail is the camera path's position every 0.5 s and at its end.
// Two keys make the Hermite path a straight line at constant speed (both tangents the chord over
// the time), so the points are at x = 10 · t / 2.2 (closed form).
TEST(SceneFile, TrailFollowsACameraPathRelativeToTheSceneFile) {
  const std::filesystem::path folder = std::filesystem::path(FOREST_TEST_OUTPUT) / "scene-trail";
  std::filesystem::create_directories(folder / "paths");
  {
    std::ofstream path(folder / "paths" / "line.toml");
    path << "[[key]]\nt = 0.0\nposition = [0.0, 1.7, 5.0]\n[[key]]\nt = 2.2\nposition = [10.0, 1.7, 5.0]\n";
  }
  const std::filesystem::path sceneFile = folder / "scenes" / "trail.toml";
  const std::string text = "[terrain]\n[vegetation]\n[vegetation.trail]\npath = \"../paths/line.toml\"\n";
  std::filesystem::create_directories(sceneFile.parent_path());
  std::ofstream(sceneFile) << text;
  const Scene scene = loadScene(sceneFile);
  ASSERT_TRUE(scene.vegetation && scene.vegetation->trail);
  const std::vector<glm::dvec2>& points = scene.vegetation->trail->points;
  ASSERT_EQ(points.size(), 6u);  // t = 0, 0.5, 1, 1.5, 2 and the end, 2.2
  for (size_t i = 0; i < points.size(); ++i) {
    const double t = std::min(0.5 * static_cast<double>(i), 2.2);
    EXPECT_NEAR(points[i].x, 10.0 * t / 2.2, 1e-9) << i;
    EXPECT_NEAR(points[i].y, 5.0, 1e-9) << i;
  }
  EXPECT_THAT(errorOf("[terrain]\n[vegetation]\n[vegetation.trail]\npath = \"no-such-path.toml\"\n"), HasSubstr("no camera-path file"));
  EXPECT_THAT(errorOf("[terrain]\n[vegetation]\n[vegetation.trail]\npath = \"\"\n"), HasSubstr("expected a non-empty string"));
  EXPECT_THAT(errorOf("[terrain]\n[vegetation]\n[vegetation.trail]\npath = \"x.toml\"\npoints = [0.0, 0.0, 1.0, 1.0]\n"),
              HasSubstr("not both"));
}

TEST(SceneFile, VegetationAreaIsARectangleThatRoundTrips) {
  const Scene scene = parseScene("[terrain]\n[vegetation]\narea = [-100.0, -50.0, 50.0, 100.0]\n", "area.toml");
  ASSERT_TRUE(scene.vegetation && scene.vegetation->area);
  EXPECT_EQ(*scene.vegetation->area, glm::dvec4(-100.0, -50.0, 50.0, 100.0));
  const Scene again = parseScene(sceneToToml(scene), "again.toml");
  EXPECT_EQ(again.vegetation->area, scene.vegetation->area);
  EXPECT_THAT(errorOf("[terrain]\n[vegetation]\narea = [0.0, 0.0, 0.0, 1.0]\n"), HasSubstr("x0 < x1 and z0 < z1"));
  EXPECT_THAT(errorOf("[terrain]\n[vegetation]\narea = [0.0, 0.0, 1.0]\n"), HasSubstr("vegetation.area"));
}

TEST(SceneFile, BadTerrainValuesNameTheKey) {
  EXPECT_THAT(errorOf("[terrain]\nsize = -2000\n"), HasSubstr("bad.toml:2:8: terrain.size = -2000: expected a number in [64, 65536]"));
  EXPECT_THAT(errorOf("[terrain]\nsamples = 0\n"), HasSubstr("terrain.samples = 0: expected an integer in [65, 8193]"));
  EXPECT_THAT(errorOf("[terrain]\nsamples = 1000\n"), HasSubstr("terrain.samples: samples - 1 must be a multiple of 64"));
  EXPECT_THAT(errorOf("[terrain]\noctaves = 17\n"), HasSubstr("terrain.octaves = 17: expected an integer in [1, 16]"));
  EXPECT_THAT(errorOf("[terrain]\nheight_min = 10\nheight_max = 5\n"), HasSubstr("terrain.height_max: must be greater"));
  EXPECT_THAT(errorOf("[terrain]\nlod_error_pixels = 0\n"), HasSubstr("terrain.lod_error_pixels = 0"));
  EXPECT_THAT(errorOf("[terrain]\nseed = -1\n"), HasSubstr("terrain.seed = -1"));
  EXPECT_THAT(errorOf("[terrain]\nsize = nan\n"), HasSubstr("terrain.size = nan"));
  EXPECT_THAT(errorOf("[terrain]\nocatves = 3\n"), HasSubstr("unknown key 'terrain.ocatves'"));
}

TEST(SceneFile, VegetationSectionLoadsRoundTripsAndNeedsTerrain) {
  const std::string text =
      "[terrain]\n[vegetation]\ncount = 300\nlod_distances = [40.0, 90.0]\nwind_direction = [0.0, 2.0]\n"
      "[vegetation.broadleaf]\nshare = 0.25\nmax_slope_deg = 20.0\n";
  const Scene scene = parseScene(text, "v.toml");
  ASSERT_TRUE(scene.vegetation.has_value());
  EXPECT_EQ(scene.vegetation->count, 300);
  EXPECT_EQ(glm::dvec2(scene.vegetation->lod_distances), glm::dvec2(40.0, 90.0));
  EXPECT_TRUE(std::isinf(scene.vegetation->lod_distances.z));  // two distances: no LOD3
  EXPECT_EQ(scene.vegetation->wind_direction, glm::dvec2(0.0, 1.0));  // normalised
  EXPECT_EQ(scene.vegetation->broadleaf.share, 0.25);
  EXPECT_EQ(scene.vegetation->conifer.share, VegetationSettings{}.conifer.share);
  const Scene back = parseScene(sceneToToml(scene), "roundtrip.toml");
  ASSERT_TRUE(back.vegetation.has_value());
  EXPECT_EQ(back.vegetation->broadleaf.max_slope_deg, 20.0);
  EXPECT_EQ(back.vegetation->lod_distances, scene.vegetation->lod_distances);
  EXPECT_EQ(back.vegetation->wind_direction, scene.vegetation->wind_direction);
  const std::string noTerrain = errorOf("[vegetation]\ncount = 10\n");
  EXPECT_THAT(noTerrain, HasSubstr("bad.toml:1:1: [vegetation]: needs a [terrain] section"));
  EXPECT_THAT(noTerrain, Not(HasSubstr("vegetation.vegetation")));
}

TEST(SceneFile, BadVegetationValuesNameTheKey) {
  EXPECT_THAT(errorOf("[terrain]\n[vegetation]\ncount = -5\n"), HasSubstr("vegetation.count = -5: expected an integer in [0, 1000000]"));
  EXPECT_THAT(errorOf("[terrain]\n[vegetation]\nlod0_triangles = 50000\n"), HasSubstr("vegetation.lod0_triangles = 50000"));
  EXPECT_THAT(errorOf("[terrain]\n[vegetation]\nlod_distances = [90.0, 40.0]\n"), HasSubstr("vegetation.lod_distances: each distance must be greater"));
  EXPECT_THAT(errorOf("[terrain]\n[vegetation]\nlod_distances = [40.0, 90.0, 80.0]\n"), HasSubstr("vegetation.lod_distances: each distance must be greater"));
  EXPECT_THAT(errorOf("[terrain]\n[vegetation]\nlod_distances = [40.0]\n"), HasSubstr("vegetation.lod_distances = [ 40.0 ]: expected an array of 3 numbers"));
  const Scene three = parseScene("[terrain]\n[vegetation]\nlod_distances = [40.0, 90.0, 300.0]\n", "v3.toml");
  EXPECT_EQ(three.vegetation->lod_distances, glm::dvec3(40.0, 90.0, 300.0));
  EXPECT_EQ(parseScene(sceneToToml(three), "roundtrip.toml").vegetation->lod_distances, three.vegetation->lod_distances);
  EXPECT_THAT(errorOf("[terrain]\n[vegetation]\nwind_direction = [0.0, 0.0]\n"), HasSubstr("vegetation.wind_direction: must be a non-zero"));
  EXPECT_THAT(errorOf("[terrain]\n[vegetation.conifer]\nspacing = 0.1\n"), HasSubstr("vegetation.conifer.spacing = 0.1"));
  EXPECT_THAT(errorOf("[terrain]\n[vegetation.oak]\nshare = 1.0\n"), HasSubstr("unknown key 'vegetation.oak'"));
  EXPECT_THAT(errorOf("[terrain]\n[vegetation]\nforce_lod0 = 1\n"), HasSubstr("vegetation.force_lod0 = 1: expected true or false"));
}

// [vegetation.stands] (docs/scene-format.md): read, range-checked, written back; absent by default.
TEST(SceneFile, StandsSectionLoadsRoundTripsAndIsChecked) {
  EXPECT_FALSE(parseScene("[terrain]\n[vegetation]\n", "v.toml").vegetation->stands.has_value());
  const Scene scene =
      parseScene("[terrain]\n[vegetation]\n[vegetation.stands]\ncover = 0.04\nfeature_m = 150.0\nmeadow = 0.003\n", "s.toml");
  ASSERT_TRUE(scene.vegetation->stands.has_value());
  EXPECT_EQ(scene.vegetation->stands->cover, 0.04);
  EXPECT_EQ(scene.vegetation->stands->feature_m, 150.0);
  EXPECT_EQ(scene.vegetation->stands->edge, StandSettings{}.edge);
  EXPECT_EQ(scene.vegetation->stands->meadow, 0.003);
  const Scene back = parseScene(sceneToToml(scene), "roundtrip.toml");
  ASSERT_TRUE(back.vegetation->stands.has_value());
  EXPECT_EQ(back.vegetation->stands->cover, 0.04);
  EXPECT_EQ(back.vegetation->stands->meadow, 0.003);
  EXPECT_THAT(errorOf("[terrain]\n[vegetation.stands]\ncover = 2.0\n"), HasSubstr("vegetation.stands.cover = 2.0: expected a number in [0.01, 0.95]"));
  EXPECT_THAT(errorOf("[terrain]\n[vegetation.stands]\nfeature_m = 5.0\n"), HasSubstr("vegetation.stands.feature_m = 5.0"));
  EXPECT_THAT(errorOf("[terrain]\n[vegetation.stands]\nedge = 0.0\n"), HasSubstr("vegetation.stands.edge = 0.0"));
  EXPECT_THAT(errorOf("[terrain]\n[vegetation]\ngrid = 10\n[vegetation.stands]\n"), HasSubstr("vegetation.grid: a grid places trees evenly"));
}

TEST(Props, MovesReportTheBoxesThatChanged) {
  std::vector<PropBox> props(3);
  props[1].min = {5, 0, 5};
  props[1].max = {6, 2, 7};
  const auto changed = moveProps(props, {{1, {10, 0, 10}}, {2, props[2].min}, {1, {11, 0, 10}}});
  EXPECT_EQ(changed, std::vector<std::uint32_t>{1});  // prop 2 did not move
  EXPECT_EQ(props[1].min, glm::dvec3(11, 0, 10));
  EXPECT_EQ(props[1].max, glm::dvec3(12, 2, 12));  // size kept
  EXPECT_THROW(moveProps(props, {{3, {0, 0, 0}}}), InputError);
}

TEST(SceneFile, EmptyFileGivesDefaults) {
  const Scene scene = parseScene("", "empty.toml");
  EXPECT_EQ(scene.render.width, RenderSettings{}.width);
  EXPECT_TRUE(scene.props.empty());
}

TEST(SceneFile, UnknownKeyNamesFileLineAndKey) {
  const std::string e = errorOf("[camera]\nfovy_deg = 50\nfvoy_deg = 60\n");
  EXPECT_THAT(e, HasSubstr("bad.toml:3:1"));
  EXPECT_THAT(e, HasSubstr("unknown key 'camera.fvoy_deg'"));
  EXPECT_THAT(errorOf("[camras]\n"), HasSubstr("unknown key 'camras'"));
}

TEST(SceneFile, MisspelledKeyGetsTheKeyItWasMeantToBe) {
  // above_ground is read only when present; it is still a key the schema knows and suggests.
  const std::string groud = errorOf("[camera]\nabove_groud = 2.0\n");
  EXPECT_THAT(groud, HasSubstr("unknown key 'camera.above_groud' (did you mean 'camera.above_ground'?"));
  EXPECT_THAT(groud, HasSubstr("known here: above_ground, "));
  EXPECT_THAT(errorOf("[camera]\nfvoy_deg = 60\n"), HasSubstr("did you mean 'camera.fovy_deg'?"));   // two letters swapped
  EXPECT_THAT(errorOf("[camras]\n"), HasSubstr("did you mean 'camera'?"));
  // Nothing near: no guess, only the list.
  EXPECT_THAT(errorOf("[camera]\nzoom = 2.0\n"), Not(HasSubstr("did you mean")));
}

TEST(SceneFile, WrongTypeNamesKeyValueAndExpectation) {
  const std::string e = errorOf("[camera]\nnear = \"close\"\n");
  EXPECT_THAT(e, HasSubstr("bad.toml:2:8"));
  EXPECT_THAT(e, HasSubstr("camera.near = 'close'"));
  EXPECT_THAT(e, HasSubstr("expected a finite number > 0"));
  EXPECT_THAT(errorOf("[render]\nwidth = 12.5\n"), HasSubstr("render.width = 12.5: expected an integer"));
  EXPECT_THAT(errorOf("camera = 3\n"), HasSubstr("camera = 3: expected a table"));
  EXPECT_THAT(errorOf("[sun]\ndirection = [1, 2]\n"), HasSubstr("expected an array of 3 numbers"));
}

TEST(SceneFile, OutOfRangeValuesAreRejectedNotClamped) {
  EXPECT_THAT(errorOf("[render]\nwidth = -640\n"), HasSubstr("render.width = -640: expected an integer in [1, 16384]"));
  EXPECT_THAT(errorOf("[render]\nheight = 1000000\n"), HasSubstr("render.height = 1000000"));
  EXPECT_THAT(errorOf("[camera]\nfovy_deg = 180\n"), HasSubstr("expected a number in (0, 180)"));
  EXPECT_THAT(errorOf("[camera]\nnear = 5.0\nfar = 1.0\n"), HasSubstr("camera.far: must be greater than camera.near"));
  EXPECT_THAT(errorOf("[sun]\ndirection = [0, 0, 0]\n"), HasSubstr("sun.direction: must be a non-zero vector"));
  EXPECT_THAT(errorOf("[[props]]\nmin = [0, 0, 0]\nmax = [1, 0, 1]\n"),
              HasSubstr("props[0].max: must be greater than min"));
}

TEST(SceneFile, NanAndInfinityAreRejected) {
  EXPECT_THAT(errorOf("[camera]\nfar = nan\n"), HasSubstr("camera.far = nan"));
  EXPECT_THAT(errorOf("[camera]\nposition = [0, inf, 0]\n"), HasSubstr("camera.position"));
  EXPECT_THAT(errorOf("[sun]\nambient = -nan\n"), HasSubstr("sun.ambient"));
}

TEST(SceneFile, MissingRequiredKeyIsNamed) {
  EXPECT_THAT(errorOf("[[props]]\nmin = [0, 0, 0]\n"), HasSubstr("props[0].max: missing"));
}

TEST(SceneFile, SyntaxErrorHasLineAndColumn) {
  EXPECT_THAT(errorOf("[camera\nnear = 1\n"), HasSubstr("bad.toml:1:"));
  EXPECT_THAT(errorOf("[camera\nnear = 1\n"), HasSubstr("TOML syntax error"));
}

TEST(SceneFile, MissingFileIsNamed) {
  try {
    loadScene("/nonexistent/forest.toml");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_THAT(std::string(e.what()), HasSubstr("/nonexistent/forest.toml: no such file"));
  }
}

TEST(SceneFile, ErrorsAreOneLine) {
  for (const char* text : {"[camera]\nfvoy = 1\n", "[camera]\nnear = \"x\"\n", "[render]\nwidth = -1\n"}) {
    EXPECT_THAT(errorOf(text), Not(HasSubstr("\n"))) << text;
  }
}

}  // namespace
}  // namespace forest
