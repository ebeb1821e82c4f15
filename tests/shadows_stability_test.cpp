// The stability suite: the hard cases shipped in data/stability/hard-cases.json and 10 000 random
// configurations keep every invariant with the float32 matrix the GPU gets; small camera moves
// move the shadow map's content continuously; case files give clear errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "forest/core/error.hpp"
#include "forest/shadows/cascades.hpp"
#include "forest/shadows/focus_body.hpp"
#include "forest/shadows/stability.hpp"
#include "test_paths.hpp"

namespace forest::shadows {
namespace {

using glm::dvec3;

constexpr ShadowMethod kMethods[] = {ShadowMethod::Uniform, ShadowMethod::UniformStable, ShadowMethod::Lispsm, ShadowMethod::Tsm,
                                     ShadowMethod::TsmIterative};

std::string failures(const StabilityCase& c, ShadowMethod method, const StabilityReport& report) {
  std::string text;
  for (const InvariantCheck& check : report.checks)
    if (!check.passed) text += c.name + " / " + std::string(kShadowMethodNames.name(method)) + ": " + check.name + ": " + check.detail + "\n";
  return text;
}

TEST(StabilitySuite, HardCasesKeepEveryInvariant) {
  const std::vector<StabilityCase> cases = loadStabilityCases(std::string(FOREST_REPO_DATA) + "/stability/hard-cases.json");
  ASSERT_GE(cases.size(), 25u);
  int empty = 0;
  for (const StabilityCase& c : cases) {
    for (ShadowMethod method : kMethods) {
      const ShadowSetup setup = computeShadowSetup(c.input, method);
      const StabilityReport report = checkSetupInvariants(c.input, method, setup);
      EXPECT_TRUE(report.passed()) << failures(c, method, report);
      empty += setup.empty ? 1 : 0;
    }
  }
  EXPECT_EQ(empty, 2 * static_cast<int>(std::size(kMethods)));  // camera outside S looking away; receivers behind the camera
  // The oracle case through the file: view ⟂ light, V ⊂ S, z_n 0.1, z_f 70 → n = 0.1 + √7.
  const auto oracle = std::find_if(cases.begin(), cases.end(), [](const StabilityCase& c) {
    return c.name.find("oracle") != std::string::npos;
  });
  ASSERT_NE(oracle, cases.end());
  EXPECT_NEAR(computeShadowSetup(oracle->input, ShadowMethod::Lispsm).diagnostics.n, 0.1 + std::sqrt(7.0), 1e-3);
}

TEST(StabilitySuite, TenThousandRandomConfigurationsKeepEveryInvariant) {
  constexpr std::uint64_t kSeed = 20061125;
  int failed = 0, warped = 0, empty = 0, refused = 0;
  double largest = 0.0, largestShrink = 0.0;
  for (std::uint64_t i = 0; i < 10000; ++i) {
    const StabilityCase c = randomStabilityCase(kSeed, i);
    // The stream also draws views outside the float32 domain (kMinViewDepthShare): those, and
    // only those, are refused as input errors.
    if (outsideShadowDomain(c.input)) {
      for (ShadowMethod method : kMethods) EXPECT_THROW(computeShadowSetup(c.input, method), InputError) << c.name;
      ++refused;
      continue;
    }
    for (ShadowMethod method : kMethods) {
      const ShadowSetup setup = computeShadowSetup(c.input, method);
      const StabilityReport report = checkSetupInvariants(c.input, method, setup);
      if (!report.passed() && ++failed <= 10) ADD_FAILURE() << failures(c, method, report);
      largest = std::max(largest, report.maxMapCoordinate);
      largestShrink = std::max(largestShrink, setup.diagnostics.floatShrink);
      warped += setup.diagnostics.warp > 0.0 ? 1 : 0;
      empty += setup.empty ? 1 : 0;
    }
  }
  EXPECT_EQ(failed, 0);
  EXPECT_LE(largest, 1.0);
  // The stream does reach the cases the suite exists for: fits that float32 rounding pushes out
  // of the map by more than a fixed 1e-4 guard band would absorb, real warps, and empty bodies.
  EXPECT_GT(largestShrink, 1e-4);
  EXPECT_GT(warped, 1000);
  EXPECT_GT(empty, 100);
  EXPECT_LT(refused, 500);  // the domain leaves out a sliver of the stream, not the stream
  std::printf("10000 random configurations x 5 methods: largest |coordinate| %.9f, largest float32 shrink %.2e, %d warped, %d empty, "
              "%d configurations refused (outside the float32 domain)\n",
              largest, largestShrink, warped, empty, refused);
}

// Z-partitioning: every slice of a view is a setup of its own and keeps every invariant — its B
// inside its layer in float32, the visible part of its slice (V_i ∩ S) inside the layer's x, y
// range — on the hard cases and 10 000 random configurations, K = 2, 3, 4 in turn. The slices
// cover the view without gaps: each starts at or before the previous one's far end.
TEST(StabilitySuite, EverySliceOfHardAndRandomViewsKeepsEveryInvariant) {
  std::vector<StabilityCase> cases = loadStabilityCases(std::string(FOREST_REPO_DATA) + "/stability/hard-cases.json");
  for (std::uint64_t i = 0; i < 10000; ++i) cases.push_back(randomStabilityCase(20061125, i));
  int failed = 0, setups = 0, refused = 0, warped = 0;
  for (size_t i = 0; i < cases.size(); ++i) {
    const StabilityCase& c = cases[i];
    const int k = 2 + static_cast<int>(i % 3);
    const std::vector<ShadowInput> slices = cascadeInputs(c.input, k, 0.8, 0.1);
    ASSERT_EQ(slices.size(), static_cast<size_t>(k));
    EXPECT_EQ(slices.front().camera.near, c.input.camera.near) << c.name;
    EXPECT_EQ(slices.back().camera.far, c.input.camera.far) << c.name;
    for (int s = 1; s < k; ++s) EXPECT_LE(slices[static_cast<size_t>(s)].camera.near, slices[static_cast<size_t>(s) - 1].camera.far) << c.name;
    for (int s = 0; s < k; ++s) {
      const ShadowInput& slice = slices[static_cast<size_t>(s)];
      if (outsideShadowDomain(slice)) {  // a thin slice far from the origin: refused like a thin view
        ++refused;
        continue;
      }
      for (ShadowMethod method : kMethods) {
        const ShadowSetup setup = computeShadowSetup(slice, method);
        const StabilityReport report = checkSetupInvariants(slice, method, setup);
        ++setups;
        warped += setup.diagnostics.warp > 0.0 ? 1 : 0;
        if (!report.passed() && ++failed <= 10) ADD_FAILURE() << "slice " << s << " of " << k << ": " << failures(c, method, report);
      }
    }
  }
  EXPECT_EQ(failed, 0);
  EXPECT_GT(warped, 3000);
  EXPECT_LT(refused, 1500);
  std::printf("%zu views in 2-4 slices: %d slice setups, %d warped, %d slices refused (outside the float32 domain)\n", cases.size(),
              setups, warped, refused);
}

TEST(StabilitySuite, CasesOnceFoundInAMillionStayFixed) {
  // Seed 20061125: #307775 and #750732 (scene boxes 0.3 m and 5 mm thin: the clip tolerance was
  // relative to the 4e5 m frustum, so V ∩ S stuck out of S and of B), #274972 (flat scene, eye
  // in its plane: B vanished in the last clip). Found by `forest stability --random 1000000`.
  // Seed 77: #153486 (a view 0.5 m deep looking along a 5 m thin B: rounding the shrunk uniform
  // matrix to float32 undid each 4u shrink step, so after 8 the setup gave up — it threw before,
  // then fell back to no shadows). Found by `forest stability --random 300000 --seed 77`.
  const std::pair<std::uint64_t, std::uint64_t> found[] = {{20061125, 307775}, {20061125, 750732}, {20061125, 274972}, {77, 153486}};
  for (const auto& [seed, index] : found) {
    const StabilityCase c = randomStabilityCase(seed, index);
    for (ShadowMethod method : kMethods) {
      const ShadowSetup setup = computeShadowSetup(c.input, method);
      const StabilityReport report = checkSetupInvariants(c.input, method, setup);
      EXPECT_TRUE(report.passed()) << failures(c, method, report);
      EXPECT_FALSE(setup.empty) << c.name;
      EXPECT_EQ(setup.diagnostics.fallback.find("float32"), std::string::npos) << c.name << ": " << setup.diagnostics.fallback;
    }
  }
}

// Two cases a review found with a seed the suite had not used (issue "Review fixes", item 6).
// "visible-outside": S is 2 mm wide and 945 m tall, 4e5 m from the origin; B and V ∩ S ∩ R were
// clipped separately and B came out 0.12 µm narrower on one side than what is seen, so uniform
// and lispsm left a visible vertex 0.27% outside the map. "tsm-throws": a view 6 mm deep 1.17e6 m
// from the origin; tsm threw out of the setup (and would have out of a frame).
TEST(StabilitySuite, HeldBackSeedCasesKeepTheInvariantsOrAreRefusedWithTheLimit) {
  const std::vector<StabilityCase> cases = loadStabilityCases(std::string(FOREST_REPO_DATA) + "/stability/hard-cases.json");
  const auto found = std::find_if(cases.begin(), cases.end(), [](const StabilityCase& c) {
    return c.name.find("held-back seed: visible outside") != std::string::npos;
  });
  ASSERT_NE(found, cases.end());
  for (ShadowMethod method : kMethods) {
    const ShadowSetup setup = computeShadowSetup(found->input, method);
    const StabilityReport report = checkSetupInvariants(found->input, method, setup);
    EXPECT_TRUE(report.passed()) << failures(*found, method, report);
    EXPECT_FALSE(setup.empty);
  }
  const std::string tsmThrows =
      R"({"name": "tsm-throws", "eye": [724550.9468206988, -112.03811888193773, 916369.658488275], "view_dir": [-0.2865788501699788, 0.7187463002410334, 0.6334637468119854], "up": [-0.3536481884743956, -0.6938624709098631, 0.6272860832599729], "fovy_deg": 0.912951654663078, "aspect": 0.10270475689823645, "near": 0.00012587650556458114, "far": 0.006201597228429672, "sun_dir": [0.0, -1.0, 0.0], "scene_min": [724493.7081671039, -114.33663691395485, 916362.5450877496], "scene_max": [724553.5433418854, -78.06629116457803, 916402.3586949077], "map_size": 8192, "border_texels": 0})";
  // 6.1 mm deep at 1.17e6 m: below 2⁻²³ · 1.17e6 m = 0.139 m, refused with the limit named.
  try {
    parseStabilityCases("[" + tsmThrows + "]", "t.json");
    ADD_FAILURE() << "a view 6 mm deep 1.17e6 m from the origin was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("2^-23"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("0.139 m"), std::string::npos) << e.what();
  }
  // The same view made 0.15 m deep (inside the domain): every method keeps the invariants.
  std::string deeperJson = tsmThrows;
  const std::string far = "0.006201597228429672";
  deeperJson.replace(deeperJson.find(far), far.size(), "0.15");
  const StabilityCase deeper = parseStabilityCases("[" + deeperJson + "]", "t.json").front();
  for (ShadowMethod method : kMethods) {
    const ShadowSetup setup = computeShadowSetup(deeper.input, method);
    const StabilityReport report = checkSetupInvariants(deeper.input, method, setup);
    EXPECT_TRUE(report.passed()) << failures(deeper, method, report);
  }
}

TEST(StabilitySuite, RandomCasesAreReproducibleByIndex) {
  const StabilityCase a = randomStabilityCase(7, 123), b = randomStabilityCase(7, 123), c = randomStabilityCase(7, 124);
  EXPECT_EQ(a.input.camera.position, b.input.camera.position);
  EXPECT_EQ(a.input.sunDirection, b.input.sunDirection);
  EXPECT_NE(a.input.camera.position, c.input.camera.position);
}

// Largest shift, in texels, of the visible points common to two frames (V ∩ V' ∩ S): a caster
// and the receiver point it shadows share their map position, so this is how far shadows swim.
double visibleShiftTexels(const ShadowInput& a, const ShadowInput& b, ShadowMethod method) {
  const ShadowSetup sa = computeShadowSetup(a, method), sb = computeShadowSetup(b, method);
  ConvexBody common = viewFrustumBody(a.camera);
  common.clip(viewFrustumBody(b.camera));
  common.clip(a.scene);
  double worst = 0.0;
  for (const dvec3& p : common.vertices()) {
    const glm::dvec4 ha = sa.worldToShadowClip * glm::dvec4(p, 1.0), hb = sb.worldToShadowClip * glm::dvec4(p, 1.0);
    const dvec3 qa = dvec3(ha) / ha.w, qb = dvec3(hb) / hb.w;
    worst = std::max({worst, std::abs(qa.x - qb.x), std::abs(qa.y - qb.y)});
  }
  return worst * a.mapSize / 2.0;
}

enum class Move { Forward, Sideways, Yaw, Pitch };

ShadowInput moved(ShadowInput in, Move move, double scale) {
  Camera& c = in.camera;
  switch (move) {
    case Move::Forward: c.position += 0.01 * scale * c.forward(); break;
    case Move::Sideways: c.position += 0.01 * scale * c.right(); break;
    case Move::Yaw: c.yaw += glm::radians(0.1 * scale); break;
    case Move::Pitch: c.pitch += glm::radians(0.1 * scale); break;
  }
  return in;
}

TEST(StabilitySuite, SmallCameraMovesMoveShadowsContinuously) {
  // A walker 2 m above ground, 2048² map, far 300 m in a 2 km scene; suns from 60° to 2°, views
  // from 20° up to 85° down; moves of 1 cm and 0.1°.
  //  - uniform-stable: the map is snapped to whole texels (a world-fixed grid), so a move shifts
  //    every visible point by a whole number of texels, and by at most one: the moves are smaller
  //    than a texel (≥ 0.3 m here) and the radius does not step (stableMapRadius).
  //  - the fitted maps: continuity, i.e. no jump — a 10× smaller move shifts 10× less (a C¹
  //    setup; the window 5…20 leaves room for second-order terms). tsm-iterative's focus line is
  //    a discrete choice among texel lines (TSM §6.2) and may switch between two frames, so it is
  //    exempt. How far they swim per move is a property of each method, not a correctness bound
  //    (DESIGN §10): printed, not asserted (last measured: lispsm ~100 texels for a 0.1° yaw with a
  //    10° sun — its warp is re-fitted to B every frame).
  double worst[std::size(kMethods)] = {};
  for (double elevation : {60.0, 30.0, 10.0, 2.0}) {
    for (double pitch : {-10.0, -45.0, -85.0, 20.0}) {
      ShadowInput in;
      in.scene = {dvec3(-1000, -10, -1000), dvec3(1000, 60, 1000)};
      in.camera.position = {3, 2, 7};
      in.camera.yaw = glm::radians(20.0);
      in.camera.pitch = glm::radians(pitch);
      in.camera.far = 300.0;
      const double e = glm::radians(elevation);
      in.sunDirection = {0.6 * std::cos(e), -std::sin(e), 0.8 * std::cos(e)};
      for (size_t m = 0; m < std::size(kMethods); ++m) {
        for (Move move : {Move::Forward, Move::Sideways, Move::Yaw, Move::Pitch}) {
          const double shift = visibleShiftTexels(in, moved(in, move, 1.0), kMethods[m]);
          worst[m] = std::max(worst[m], shift);
          const std::string where = std::string(kShadowMethodNames.name(kMethods[m])) + " sun " + std::to_string(elevation) +
                                    "° pitch " + std::to_string(pitch) + "° move " + std::to_string(static_cast<int>(move));
          if (kMethods[m] == ShadowMethod::UniformStable) {
            EXPECT_LE(std::round(shift), 1.0) << where;
            EXPECT_NEAR(shift, std::round(shift), 1e-6) << where;  // whole texels only: no swimming
            continue;
          }
          if (shift > 0.05 && kMethods[m] != ShadowMethod::TsmIterative) {
            const double small = visibleShiftTexels(in, moved(in, move, 0.1), kMethods[m]);
            EXPECT_GT(shift / small, 5.0) << where;
            EXPECT_LT(shift / small, 20.0) << where;
          }
        }
      }
    }
  }
  for (size_t m = 0; m < std::size(kMethods); ++m)
    std::printf("[continuity] %s: largest shift of a visible point for a 1 cm / 0.1° move: %.1f texels of 2048\n",
                kShadowMethodNames.name(kMethods[m]).data(), worst[m]);
}

TEST(StabilityCases, ErrorsNameTheCaseAndTheField) {
  const std::string good =
      R"({"name": "ok", "eye": [0, 5, 0], "view_dir": [0, 0, -1], "up": [0, 1, 0], "fovy_deg": 60, "aspect": 1.5,
          "near": 0.1, "far": 70, "sun_dir": [0.3, -0.8, 0.2], "scene_min": [-100, 0, -100], "scene_max": [100, 20, 100]})";
  EXPECT_EQ(parseStabilityCases("[" + good + "]", "t.json").size(), 1u);
  auto expectError = [&](const std::string& text, const std::string& expected) {
    try {
      parseStabilityCases(text, "t.json");
      ADD_FAILURE() << "no error for " << text;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  };
  auto with = [&](const std::string& from, const std::string& to) {
    std::string text = good;
    text.replace(text.find(from), from.size(), to);
    return "[" + text + "]";
  };
  expectError(with("\"sun_dir\": [0.3, -0.8, 0.2]", "\"sun_dir\": [0, 0, 0]"), "t.json: case 1 ('ok'): sun_dir: expected a non-zero direction");
  expectError(with("\"near\": 0.1", "\"near\": 80"), "far: expected far > near (80), got 70");
  expectError(with("\"near\": 0.1", "\"near\": -1"), "near: expected a number > 0, got -1");
  expectError(with("\"fovy_deg\": 60", "\"fovy_deg\": 180"), "fovy_deg: expected 0 < fovy_deg < 180");
  expectError(with("\"eye\": [0, 5, 0]", "\"eye\": [0, 5]"), "eye: expected [x, y, z], got [0,5]");
  expectError(with("\"aspect\": 1.5", "\"aspect\": \"wide\""), "aspect: expected a number, got \"wide\"");
  expectError(with("\"up\": [0, 1, 0]", "\"up\": [0, 0, -2]"), "view_dir, up: up vector: expected a direction not parallel");
  expectError(with("\"aspect\": 1.5", "\"aspect\": 1.5, \"fov\": 3"), "fov: unknown field");
  expectError(with("\"far\": 70,", ""), "far: missing");
  expectError("[" + good, "t.json: invalid JSON at byte");
  expectError("{\"cases\": 3}", "expected an array of cases");
  // NaN cannot be written in JSON; a huge exponent overflows to a non-finite number.
  expectError(with("\"near\": 0.1", "\"near\": 1e999"), "t.json: invalid JSON: ");
}

}  // namespace
}  // namespace forest::shadows
