// Caster selection in light space: exact for boxes, conservative against rays sampled from the
// receivers towards the sun, and the footprint grid selects exactly what all pairs would.
#include <gtest/gtest.h>

#include <limits>
#include <random>

#include "forest/core/error.hpp"
#include "forest/shadows/casters.hpp"
#include "forest/shadows/focus_body.hpp"

namespace forest::shadows {
namespace {

using glm::dvec3;

const dvec3 kNoon(0, -1, 0);

TEST(CasterSelection, SweptBoxMeetsOnlyWhatIsDownstream) {
  const Aabb receiver{dvec3(0, 0, 0), dvec3(1, 1, 1)};
  EXPECT_TRUE(sweptBoxMeetsBox({dvec3(0.2, 5, 0.2), dvec3(0.8, 6, 0.8)}, kNoon, receiver));      // above it
  EXPECT_FALSE(sweptBoxMeetsBox({dvec3(0.2, -6, 0.2), dvec3(0.8, -5, 0.8)}, kNoon, receiver));    // below it
  EXPECT_FALSE(sweptBoxMeetsBox({dvec3(2, 5, 0), dvec3(3, 6, 1)}, kNoon, receiver));              // beside it
  EXPECT_TRUE(sweptBoxMeetsBox({dvec3(0.5, 0.5, 0.5), dvec3(2, 2, 2)}, kNoon, receiver));         // overlapping
  // A low sun from +x: a box 100 m upsun, 1.7 m up, shadows it; the same box downsun does not.
  const dvec3 lowSun = glm::normalize(dvec3(1, -0.02, 0));
  EXPECT_TRUE(sweptBoxMeetsBox({dvec3(-100, 2, 0), dvec3(-99, 3, 1)}, lowSun, receiver));
  EXPECT_FALSE(sweptBoxMeetsBox({dvec3(101, 2, 0), dvec3(102, 3, 1)}, lowSun, receiver));
  EXPECT_FALSE(sweptBoxMeetsBox({dvec3(-100, 4, 0), dvec3(-99, 5, 1)}, lowSun, receiver));  // its shadow passes above
}

struct RandomScene {
  std::vector<Aabb> boxes;
  std::vector<Aabb> receivers;
};

RandomScene randomScene(std::mt19937_64& rng, int count) {
  std::uniform_real_distribution<double> position(-200.0, 200.0), height(0.0, 30.0), size(0.2, 15.0);
  RandomScene scene;
  for (int i = 0; i < count; ++i) {
    const dvec3 min(position(rng), height(rng), position(rng));
    scene.boxes.push_back({min, min + dvec3(size(rng), size(rng), size(rng))});
  }
  for (int i = 0; i < count; i += 7) scene.receivers.push_back(scene.boxes[i]);
  return scene;
}

// Does the ray p + s·(−l), s > 0, towards the sun pass through the box?
bool rayToSunHits(const dvec3& p, const dvec3& l, const Aabb& box) {
  double enter = 1e-9, leave = std::numeric_limits<double>::infinity();
  for (int axis = 0; axis < 3; ++axis) {
    const double d = -l[axis];
    if (d == 0.0) {
      if (p[axis] < box.min[axis] || p[axis] > box.max[axis]) return false;
      continue;
    }
    double t0 = (box.min[axis] - p[axis]) / d, t1 = (box.max[axis] - p[axis]) / d;
    if (t0 > t1) std::swap(t0, t1);
    enter = std::max(enter, t0);
    leave = std::min(leave, t1);
  }
  return enter <= leave;
}

TEST(CasterSelection, EveryBoxBetweenAReceiverAndTheSunIsSelected) {
  std::mt19937_64 rng(2011);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int occluders = 0, selectedTotal = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const RandomScene scene = randomScene(rng, 300);
    const double elevation = glm::radians(1.0 + 88.0 * unit(rng)), azimuth = 2.0 * 3.14159265 * unit(rng);
    const dvec3 l(std::cos(elevation) * std::cos(azimuth), -std::sin(elevation), std::cos(elevation) * std::sin(azimuth));
    const CasterSelector selector(l, scene.receivers);
    const std::vector<std::uint32_t> selected = selector.select(scene.boxes);
    std::vector<bool> isSelected(scene.boxes.size(), false);
    for (std::uint32_t i : selected) isSelected[i] = true;
    selectedTotal += static_cast<int>(selected.size());
    // Points inside and on the faces of every receiver; every box a ray to the sun crosses.
    for (const Aabb& r : scene.receivers) {
      for (int sample = 0; sample < 64; ++sample) {
        dvec3 p(r.min.x + unit(rng) * r.extent().x, r.min.y + unit(rng) * r.extent().y, r.min.z + unit(rng) * r.extent().z);
        const int face = sample % 7;  // 6 = interior
        if (face < 6) p[face / 2] = face % 2 ? r.max[face / 2] : r.min[face / 2];
        for (size_t b = 0; b < scene.boxes.size(); ++b) {
          if (rayToSunHits(p, l, scene.boxes[b])) {
            ++occluders;
            ASSERT_TRUE(isSelected[b]) << "trial " << trial << ": box " << b << " shadows a receiver point but was not selected";
          }
        }
      }
    }
    // The grid selects exactly what testing every pair would.
    for (size_t b = 0; b < scene.boxes.size(); ++b) {
      bool any = false;
      for (const Aabb& r : scene.receivers) any = any || sweptBoxMeetsBox(scene.boxes[b], l, r);
      ASSERT_EQ(any, static_cast<bool>(isSelected[b])) << "trial " << trial << " box " << b;
    }
  }
  EXPECT_GT(occluders, 1000);  // the samples do find occluders
  EXPECT_LT(selectedTotal, 40 * 300);  // and selection is not "everything"
}

TEST(CasterSelection, NoReceiversSelectNothingAndBadLightIsRejected) {
  const CasterSelector none(kNoon, {});
  const Aabb box{dvec3(0), dvec3(1)};
  EXPECT_FALSE(none.needed(box));
  EXPECT_THROW(CasterSelector(dvec3(0.0), std::span<const Aabb>(&box, 1)), InputError);
}

TEST(CasterSelection, FrustumBodyOverlapIsConservative) {
  Camera camera;
  camera.position = {0, 2, 0};
  camera.far = 100.0;
  const ConvexBody frustum = viewFrustumBody(camera);
  EXPECT_TRUE(mayIntersect(frustum, {dvec3(-1, 0, -20), dvec3(1, 4, -18)}));   // ahead
  EXPECT_FALSE(mayIntersect(frustum, {dvec3(-1, 0, 18), dvec3(1, 4, 20)}));    // behind
  EXPECT_FALSE(mayIntersect(frustum, {dvec3(-1, 0, -220), dvec3(1, 4, -218)})); // past far
  EXPECT_FALSE(mayIntersect(frustum, {dvec3(60, 0, -20), dvec3(62, 4, -18)}));  // far to the side
  EXPECT_FALSE(mayIntersect(ConvexBody(), {dvec3(0), dvec3(1)}));
}

}  // namespace
}  // namespace forest::shadows
