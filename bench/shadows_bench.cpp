// shadows_bench: microseconds per shadow setup by method (B with 20–60 vertices), and how many
// casters the light-space selection from visible receivers keeps against the focus body of the
// whole frustum, on a 5000-tree box forest, and the analytic aliasing per method in the thesis demo
// configuration. Prints measured numbers; run by hand:
//   build/release/bench/shadows_bench
#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <vector>

#include "forest/core/random.hpp"
#include "forest/shadows/aliasing.hpp"
#include "forest/shadows/casters.hpp"
#include "forest/shadows/focus_body.hpp"
#include "forest/shadows/stability.hpp"

namespace {

using namespace forest;
using namespace forest::shadows;
using glm::dvec3;
using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

void benchmarkSetups() {
  // Configurations from the random stability stream whose B has 20–60 vertices.
  std::vector<ShadowInput> inputs;
  size_t vertexSum = 0;
  for (std::uint64_t i = 0; inputs.size() < 2000; ++i) {
    const StabilityCase c = randomStabilityCase(1, i);
    const ShadowSetup s = computeShadowSetup(c.input, ShadowMethod::Lispsm);
    if (s.diagnostics.bodyVertices >= 20 && s.diagnostics.bodyVertices <= 60) {
      inputs.push_back(c.input);
      vertexSum += s.diagnostics.bodyVertices;
    }
  }
  std::printf("Shadow setup, %zu configurations with 20-60 vertices in B (mean %.1f):\n", inputs.size(),
              static_cast<double>(vertexSum) / static_cast<double>(inputs.size()));
  double bodyMicroseconds = 0.0;
  {
    int rounds = 0;
    const auto start = Clock::now();
    do {
      for (const ShadowInput& in : inputs) {
        const ConvexBody b = computeFocusBody(in.camera, in.sunDirection, in.scene, in.receivers);
        if (b.polygons().size() == 12345) std::puts("");  // keep the work
      }
      ++rounds;
    } while (secondsSince(start) < 0.5);
    bodyMicroseconds = 1e6 * secondsSince(start) / (static_cast<double>(rounds) * static_cast<double>(inputs.size()));
  }
  std::printf("  %-16s %8.1f us\n", "focus body only", bodyMicroseconds);
  for (ShadowMethod method : {ShadowMethod::Uniform, ShadowMethod::UniformStable, ShadowMethod::Lispsm, ShadowMethod::Tsm,
                              ShadowMethod::TsmIterative}) {
    int rounds = 0;
    double checksum = 0.0;
    const auto start = Clock::now();
    do {
      for (const ShadowInput& in : inputs) checksum += computeShadowSetup(in, method).worldToShadowClip[0][0];
      ++rounds;
    } while (secondsSince(start) < 0.5);
    const double us = 1e6 * secondsSince(start) / (static_cast<double>(rounds) * static_cast<double>(inputs.size()));
    std::printf("  %-16s %8.1f us per setup (%.1fx the focus body)%s\n", std::string(kShadowMethodNames.name(method)).c_str(), us,
                us / bodyMicroseconds, std::isfinite(checksum) ? "" : " !");
  }
}

// The thesis demo configuration (ch. 10): fov 60°, near 0.1, far 70, 800×600, 2048² map, a
// 200 m × 200 m heightfield 15 m high, eye 2 m above the ground looking level (5° down); suns at
// 15°, 45°, 75° from behind-left, and dueling frusta at 30° (looking along the light and into it).
void benchmarkAliasing() {
  struct Scenario {
    const char* name;
    double elevationDeg, azimuthDeg, pitchDeg;
  };
  const Scenario scenarios[] = {{"sun 15°", 15, 135, -5},         {"sun 45°", 45, 135, -5},
                                {"sun 75°", 75, 135, -5},         {"dueling, sun behind", 30, 0, -30},
                                {"dueling, sun ahead", 30, 180, 30}};
  std::printf("\nAnalytic aliasing, thesis demo configuration (fov 60, near 0.1, far 70, 800x600, 2048^2):\n");
  std::printf("  %-20s %-15s %10s %10s %10s %10s %12s %12s\n", "scenario", "method", "max rel", "p95 rel", "max/floor",
              "surf p95", "surf max px", "storage S");
  for (const Scenario& sc : scenarios) {
    ShadowInput in;
    in.scene = {dvec3(-100, 0, -100), dvec3(100, 15, 100)};
    in.camera.position = {0, 2, 0};
    in.camera.yaw = 0.0;  // looking along −z
    in.camera.pitch = glm::radians(sc.pitchDeg);
    in.camera.fovy = glm::radians(60.0);
    in.camera.aspect = 800.0 / 600.0;
    in.camera.near = 0.1;
    in.camera.far = 70.0;
    in.mapSize = 2048;
    const double e = glm::radians(sc.elevationDeg), a = glm::radians(sc.azimuthDeg);
    // Azimuth 0: the light travels along −z (the view's way, sun behind); 180: towards the eye.
    in.sunDirection = {std::cos(e) * std::sin(a), -std::sin(e), -std::cos(e) * std::cos(a)};
    AliasingOptions options;
    options.width = 800;
    options.height = 600;
    for (ShadowMethod method : {ShadowMethod::Uniform, ShadowMethod::UniformStable, ShadowMethod::Lispsm, ShadowMethod::Tsm,
                                ShadowMethod::TsmIterative}) {
      const ShadowSetup setup = computeShadowSetup(in, method);
      const AliasingReport r = analyseAliasing(in, setup, options);
      std::printf("  %-20s %-15s %10.2f %10.2f %10.2f %10.2f %12.2f %12.3g\n", sc.name,
                  std::string(kShadowMethodNames.name(method)).c_str(), r.perspective.max, r.perspective.p95,
                  r.floor > 0.0 ? r.perspective.max / r.floor : 0.0, r.surfacePixels.p95, r.surfacePixels.max, r.storageFactor);
    }
  }
  std::printf("  (rel: eq. 8.1 perspective part, tangent units per map width; floor: ln(z1/z0), eq. 8.4;\n"
              "   surf: with the ground normal, pixels per texel; storage S = R^2 max m_s max m_t / (W H))\n");
}

struct Forest {
  std::vector<Aabb> objects;  // ground tiles, then trees
  size_t tiles = 0;
  Aabb scene;
};

Forest makeForest() {
  Forest f;
  constexpr double kSize = 2000.0, kTile = kSize / 64.0;
  for (int z = 0; z < 64; ++z)
    for (int x = 0; x < 64; ++x) {
      const dvec3 min(-kSize / 2 + x * kTile, 0.0, -kSize / 2 + z * kTile);
      f.objects.push_back({min, min + dvec3(kTile, 2.0, kTile)});
    }
  f.tiles = f.objects.size();
  SplitMix64 random(5000);
  auto unit = [&] { return random.unit(); };
  for (int i = 0; i < 5000; ++i) {
    const dvec3 base(-kSize / 2 + kSize * unit(), 1.0, -kSize / 2 + kSize * unit());
    const double height = 8.0 + 12.0 * unit(), radius = 2.0 + 2.0 * unit();
    f.objects.push_back({base - dvec3(radius, 0.0, radius), base + dvec3(radius, height, radius)});
  }
  for (const Aabb& b : f.objects) f.scene.extend(b);
  return f;
}

void benchmarkCasters() {
  const Forest forest = makeForest();
  std::printf("\nCasters on a 2 km box forest (%zu ground tiles + %zu trees), camera 2 m up:\n",
              forest.tiles, forest.objects.size() - forest.tiles);
  std::printf("  %-6s %-8s %-5s | %-19s | %-18s | %s\n", "z_f", "sun elev", "yaw", "receivers (frustum)", "casters: receivers",
              "casters: frustum B   selection time");
  for (double far : {1000.0, 250.0})
  for (double elevation : {60.0, 30.0, 10.0}) {
    const double e = glm::radians(elevation);
    const dvec3 l(0.6 * std::cos(e), -std::sin(e), 0.8 * std::cos(e));
    for (double yaw : {0.0, 90.0, 200.0}) {
      Camera camera;
      camera.position = {0.0, 2.0, 0.0};
      camera.yaw = glm::radians(yaw);
      camera.pitch = glm::radians(-5.0);
      camera.far = far;
      const ConvexBody frustum = viewFrustumBody(camera);
      std::vector<Aabb> receivers;
      for (const Aabb& b : forest.objects)
        if (mayIntersect(frustum, b)) receivers.push_back(b);
      const auto start = Clock::now();
      const CasterSelector selector(l, receivers);
      const size_t fromReceivers = selector.select(forest.objects).size();
      const double ms = 1e3 * secondsSince(start);
      const ConvexBody body = computeFocusBody(camera, l, forest.scene);
      size_t fromBody = 0;
      for (const Aabb& b : forest.objects) fromBody += mayIntersect(body, b) ? 1 : 0;
      std::printf("  %4.0f m  %6.0f°  %4.0f° | %19zu | %18zu | %18zu   %6.2f ms\n", far, elevation, yaw, receivers.size(),
                  fromReceivers, fromBody, ms);
    }
  }
  std::printf("  Receivers here are the objects in the frustum up to z_f: an upper bound of the visible set\n"
              "  (no occlusion culling yet). Whole receiver boxes reach outside the frustum, so on open ground\n"
              "  they select a few more casters than the frustum's B; occlusion removes receivers (a hill\n"
              "  hides a valley), which B cannot. z_f from the visible set shrinks both.\n");
}

}  // namespace

int main() {
  benchmarkSetups();
  benchmarkAliasing();
  benchmarkCasters();
  return 0;
}
