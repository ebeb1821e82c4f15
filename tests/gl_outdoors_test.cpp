// Ground and sky that read as outdoors (issue "A forest to walk through"): the sky is the gradient
// and sun disc of its closed form (tests/gl_test_support.hpp: skyDisplay), the same twice; the
// terrain's material lays forest floor under the stands and grass in the clearings.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <vector>

#include "forest/core/scene.hpp"
#include "forest/render/frame.hpp"
#include "forest/vegetation/forest.hpp"
#include "gl_test_support.hpp"
#include "test_paths.hpp"

namespace forest::test {
namespace {

using glm::dvec3;

constexpr int kWidth = 240, kHeight = 160;

class OutdoorsGl : public GlTest {};

// The sky's display value at pixel (x, y) of the camera's image, from its closed form along the
// pixel's ray (skyDisplay); none on the sun disc's 0.2°-wide edge ramp, where float32 may fall on
// either side of the step.
std::optional<dvec3> skyExpectedAt(const Camera& camera, int x, int y, const Scene& scene) {
  const dvec3 toSun = -scene.sun.direction;
  const dvec3 ray = glm::normalize(pixelPosition(camera, x, y, 0.5f, kWidth, kHeight) - camera.position);
  if (const double c = glm::dot(ray, toSun); c > 0.99985 && c < 0.99990) return std::nullopt;
  return skyDisplay(ray, scene.render.sky_color, toSun, scene.sun.color, true);
}

// An empty scene looked at toward a sun 20° up: every pixel is sky, equal to the closed form along
// its ray within 1.5 of 255 (rounding, float32), except on the disc's 0.2°-wide edge ramp; the
// pixel toward the sun is the disc, white; the horizon is paler than the view's top; a second
// render gives the same pixels. A flat sky, a missing disc or a gradient the wrong way fails.
TEST_F(OutdoorsGl, SkyIsTheGradientOfItsClosedFormWithTheSunsDisc) {
  Scene scene;
  const double elevation = glm::radians(20.0);
  scene.sun.direction = -dvec3(0.0, std::sin(elevation), -std::cos(elevation));  // light travels toward +z, down
  render::Frame frame(scene, kWidth, kHeight);
  const Camera camera = cameraAt(dvec3(0.0, 2.0, 0.0), 0.0, 20.0, 500.0, static_cast<double>(kWidth) / kHeight);  // facing −z, the sun
  frame.render(camera, 0.0, render::FrameSettings{});
  const Image8 first = frame.readColor();
  frame.render(camera, 0.0, render::FrameSettings{});
  EXPECT_EQ(frame.readColor().pixels, first.pixels);  // a pure function of the view
  int compared = 0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      const std::optional<dvec3> expected = skyExpectedAt(camera, x, y, scene);
      if (!expected) continue;
      const size_t top = static_cast<size_t>(kHeight - 1 - y) * kWidth + static_cast<size_t>(x);
      for (int k = 0; k < 3; ++k) ASSERT_NEAR(first.pixels[top * 4 + static_cast<size_t>(k)], (*expected)[k], 1.5) << x << ", " << y;
      ++compared;
    }
  EXPECT_GT(compared, kWidth * kHeight * 99 / 100);
  // The sun is at the view's centre (pitch 20° = its elevation): the disc, white.
  const size_t centre = static_cast<size_t>(kHeight / 2) * kWidth + kWidth / 2;
  for (int k = 0; k < 3; ++k) EXPECT_GE(first.pixels[centre * 4 + static_cast<size_t>(k)], 254) << k;
  // Paler (more red) at the bottom row, 10° above the horizon, than at the top, 30°+ up.
  const size_t bottom = static_cast<size_t>(kHeight - 1) * kWidth;
  EXPECT_GT(first.pixels[bottom * 4], first.pixels[0] + 5);
}

// Distance haze (shaders/lighting.frag, HAZE): a pixel of the ground at camera distance r is the
// haze-free pixel's linear colour L0 faded toward the haze colour H along its ray by
// exp(-density · r), H = the horizon's colour + 0.25 × the sun's colour × max(ray · toSun, 0)^8.
// L0 comes from the same view rendered without haze; the expected display value is within the two
// images' 8-bit conversion (a level each, the clear one's carried through the fade) and the display
// encoding's 0.12 of 255. A frame that leaves the haze out (e.g. the program compiled without it) is off by
// tens of levels far away. The pixels where nothing was drawn are the sky's closed form in both
// frames (as in SkyIsTheGradientOfItsClosedFormWithTheSunsDisc; the sky has no haze): a lighting
// pass that took a sky pixel for a surface, or the other way round, fails there.
TEST_F(OutdoorsGl, HazeFadesTheGroundTowardItsColourByDistance) {
  Scene scene;
  scene.props.push_back({dvec3(-400, -1, -400), dvec3(400, 0, 400), dvec3(0.5, 0.45, 0.3)});  // the ground, top at y = 0
  const double elevation = glm::radians(40.0);
  scene.sun.direction = -glm::normalize(dvec3(0.3, std::sin(elevation), -std::cos(elevation)));
  render::Frame frame(scene, kWidth, kHeight);
  const Camera camera = cameraAt(dvec3(0.0, 3.0, 0.0), 0.0, -4.0, 500.0, static_cast<double>(kWidth) / kHeight);
  frame.render(camera, 0.0, render::FrameSettings{});
  const Image8 clear = frame.readColor();
  render::FrameSettings hazy;
  const double density = 0.01;
  hazy.fogDensity = density;
  frame.render(camera, 0.0, hazy);
  const Image8 faded = frame.readColor();
  const std::vector<std::uint32_t> ids = frame.readObjectIds();
  const std::vector<float> depth = frame.readDepth();
  const dvec3 zenith = glm::pow(scene.render.sky_color, dvec3(2.2));
  const dvec3 horizon = zenith + 0.55 * (dvec3(0.75, 0.8, 0.85) - zenith);
  int compared = 0, farOff = 0, skyCompared = 0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      const size_t i = static_cast<size_t>(y) * kWidth + x;
      if (ids[i] == 0) {  // nothing drawn: the sky
        const std::optional<dvec3> expected = skyExpectedAt(camera, x, y, scene);
        if (!expected) continue;
        const size_t top = static_cast<size_t>(kHeight - 1 - y) * kWidth + static_cast<size_t>(x);
        for (int k = 0; k < 3; ++k) {
          ASSERT_NEAR(clear.pixels[top * 4 + static_cast<size_t>(k)], (*expected)[k], 1.5) << "sky, clear, " << x << ", " << y;
          ASSERT_NEAR(faded.pixels[top * 4 + static_cast<size_t>(k)], (*expected)[k], 1.5) << "sky, hazy, " << x << ", " << y;
        }
        ++skyCompared;
        continue;
      }
      if (ids[i] != frame.objects().propIdBase()) continue;
      const dvec3 relative = pixelPosition(camera, x, y, depth[i], kWidth, kHeight) - camera.position;
      const dvec3 ray = glm::normalize(relative);
      const dvec3 haze = horizon + 0.25 * scene.sun.color * std::pow(std::max(glm::dot(ray, -scene.sun.direction), 0.0), 8.0);
      const double kept = std::exp(-density * glm::length(relative));
      const size_t top = static_cast<size_t>(kHeight - 1 - y) * kWidth + static_cast<size_t>(x);
      for (int k = 0; k < 3; ++k) {
        const double before = clear.pixels[top * 4 + static_cast<size_t>(k)];
        const double linear = std::pow(before / 255.0, 2.2);
        const double hazed = std::clamp(haze[k] + kept * (linear - haze[k]), 1e-6, 1.0);
        const double expected = 255.0 * std::pow(hazed, 1.0 / 2.2);
        // The clear pixel's 8-bit conversion (within a level: not round-to-nearest on llvmpipe, as
        // the sky test allows) carries over scaled by d(expected)/d(before) =
        // kept · (linear / hazed)^(1 − 1/2.2); then the faded pixel's own and the encoding's 0.12.
        const double carried = kept * std::pow(std::max(linear, 1e-6) / hazed, 1.0 - 1.0 / 2.2);
        ASSERT_NEAR(faded.pixels[top * 4 + static_cast<size_t>(k)], expected, carried + 1.0 + 0.12)
            << x << ", " << y << " channel " << k;
        farOff += std::abs(expected - before) > 20.0 ? 1 : 0;
      }
      ++compared;
    }
  EXPECT_GT(compared, kWidth * kHeight / 3);
  EXPECT_GT(skyCompared, kWidth * kHeight / 4);
  EXPECT_GT(farOff, kWidth * kHeight / 20);  // the haze shows: far pixels move by over 20 levels
  EXPECT_EQ(gl::debugErrorCount(), 0u);
}

// The mean green-to-red ratio of the terrain's pixels near the eye, by night (ambient light only,
// the same for both views; no haze): under the densest stand the material is forest floor,
// (0.24, 0.19, 0.11), g/r = 0.79; in a meadow it is grass between (0.32, 0.42, 0.2) and dry grass
// (0.45, 0.42, 0.22), g/r ≥ 0.93 (shaders/terrain.frag). Without the ground cover both are grass.
// Each view rendered twice gives the same pixels.
TEST_F(OutdoorsGl, ForestFloorUnderTheStandsGrassInTheMeadows) {
  Scene scene = loadScene(std::string(FOREST_REPO_DATA) + "/scenes/forest.toml");
  scene.render.haze = 0.0;
  scene.sun.direction = glm::normalize(dvec3(0.3, 0.5, 0.2));  // travelling upward: night
  render::Frame frame(scene, kWidth, kHeight);
  const vegetation::Forest& forest = *frame.forest();
  const terrain::Terrain& terrain = *frame.terrain();
  const vegetation::StandField& stands = *forest.stands();
  // The densest stand's middle; a meadow: the first point on a 50 m grid whose density is the
  // meadow's, on gentle ground.
  const glm::dvec2 stand = vegetation::densestStand(forest);
  glm::dvec2 meadow = stand;
  for (double z = -500.0; z <= 500.0 && meadow == stand; z += 50.0)
    for (double x = -500.0; x <= 500.0; x += 50.0)
      if (stands.density(x, z) < 0.01 && terrain.normalAt(x, z).y > 0.95) {
        meadow = {x, z};
        break;
      }
  ASSERT_NE(meadow, stand);
  ASSERT_GT(stands.density(stand.x, stand.y), 0.99);
  auto meanGreenOverRed = [&](const glm::dvec2& at) {
    const Camera camera = cameraAt(dvec3(at.x, terrain.heightAt(at.x, at.y) + 1.7, at.y), 30.0, -35.0, 300.0,
                                   static_cast<double>(kWidth) / kHeight);
    frame.render(camera, 0.0, render::FrameSettings{});
    const Image8 color = frame.readColor();
    frame.render(camera, 0.0, render::FrameSettings{});
    EXPECT_EQ(frame.readColor().pixels, color.pixels);  // the material is a pure function: the same pixels twice
    const std::vector<std::uint32_t> ids = frame.readObjectIds();
    const std::vector<float> depth = frame.readDepth();
    double sum = 0.0;
    int n = 0;
    for (int y = 0; y < kHeight; ++y)
      for (int x = 0; x < kWidth; ++x) {
        const size_t i = static_cast<size_t>(y) * kWidth + x;
        const std::uint32_t first = frame.objects().terrainIdBase();
        if (ids[i] < first || ids[i] >= first + frame.objects().tileCount()) continue;  // terrain tiles only
        const dvec3 p = pixelPosition(camera, x, y, depth[i], kWidth, kHeight);
        if (glm::distance(glm::dvec2(p.x, p.z), at) > 15.0 || terrain.normalAt(p.x, p.z).y < 0.9) continue;  // near, not rock
        const size_t top = static_cast<size_t>(kHeight - 1 - y) * kWidth + static_cast<size_t>(x);
        sum += (color.pixels[top * 4 + 1] + 0.5) / (color.pixels[top * 4] + 0.5);
        ++n;
      }
    EXPECT_GT(n, 200);
    return sum / std::max(n, 1);
  };
  const double floor = meanGreenOverRed(stand), grass = meanGreenOverRed(meadow);
  std::printf("[ground] g/r under the stand at (%.0f, %.0f): %.3f; in the meadow at (%.0f, %.0f): %.3f\n", stand.x, stand.y, floor, meadow.x,
              meadow.y, grass);
  // In display values (γ 2.2) the ratio of the two materials is at most (0.79 / 0.93)^(1/2.2) = 0.929;
  // 1% for 8-bit rounding.
  EXPECT_LT(floor, grass * (std::pow(0.79 / 0.93, 1.0 / 2.2) + 0.01));
}

}  // namespace
}  // namespace forest::test
