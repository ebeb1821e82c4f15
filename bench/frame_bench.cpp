// frame_bench: per-pass time and triangles of the frame for the default forest at the walkthrough
// start, with shadow casters chosen from the visible receivers, from the frustum's focus body B,
// or all objects.   build/release/bench/frame_bench [--gl=auto|egl|osmesa] [--frames N]
#include <cstdio>
#include <string>

#include "bench_args.hpp"
#include "forest/core/resources.hpp"
#include "forest/gl/context.hpp"
#include "forest/render/frame.hpp"

int main(int argc, char** argv) {
  using namespace forest;
  const bench::BenchArgs args = bench::parseBenchArgs(argc, argv, "frame_bench");
  const int frames = args.frames;
  const Scene scene = loadScene(resourceDirectory("data") / "scenes" / "forest.toml");
  auto context = bench::benchContext(args);
  render::Frame frame(scene, args.width, args.height);
  // The walkthrough start, and a walker at the foot of the highest hill facing it (the hill hides
  // what lies behind it: receivers shrink, the frustum's B does not).
  const Camera start = frame.startCamera();
  Camera hill = start;
  {
    const terrain::Terrain& t = *frame.terrain();
    glm::dvec3 top(0.0, -1e9, 0.0);
    for (int tile = 0; tile < t.tileCount(); ++tile)
      if (t.tileBox(tile).max.y > top.y) top = glm::dvec3(t.tileBox(tile).centre().x, t.tileBox(tile).max.y, t.tileBox(tile).centre().z);
    const glm::dvec3 foot = top + glm::dvec3(150.0, 0.0, 0.0);
    hill.position = {foot.x, t.heightAt(foot.x, foot.z) + 1.7, foot.z};
    hill.yaw = glm::radians(90.0);  // looking along −x, at the hill
    hill.pitch = glm::radians(5.0);
  }
  std::printf("%dx%d, lispsm 2048², CHC++, %d frames each (after one warm-up)\n", frame.width(), frame.height(), frames);
  for (const auto& [name, camera] : {std::pair<const char*, Camera>{"walkthrough start", start}, {"facing a hill", hill}}) {
  std::printf("\n%s:\n%-13s %8s %8s %8s %8s %8s | %9s %10s %8s %10s\n", name, "casters", "geom ms", "setup ms", "shadow", "term ms",
              "light ms", "visible", "geom tris", "casters", "shadow tris");
  long long frustumTriangles = 0, receiverTriangles = 0;
  for (render::CasterSelection selection :
       {render::CasterSelection::Receivers, render::CasterSelection::FrustumBody, render::CasterSelection::All}) {
    render::FrameSettings settings;
    settings.casters = selection;
    frame.render(camera, 0.0, settings);
    render::FrameStats sum;
    render::FrameStats last;
    for (int f = 0; f < frames; ++f) {
      last = frame.render(camera, 0.0, settings);
      for (FramePass pass : kFramePassNames.values()) sum.passMs[pass] += last.passMs[pass];
    }
    std::printf("%-13s %8.2f %8.2f %8.2f %8.2f %8.2f | %9d %10lld %8d %10lld\n",
                std::string(render::kCasterSelectionNames.name(selection)).c_str(), sum.passMs[FramePass::Geometry] / frames,
                sum.passMs[FramePass::ShadowSetup] / frames, sum.passMs[FramePass::Shadow] / frames,
                sum.passMs[FramePass::ShadowTerm] / frames, sum.passMs[FramePass::Lighting] / frames,
                last.visibleObjects, last.geometryTriangles, last.casterObjects, last.shadowTriangles);
    if (selection == render::CasterSelection::Receivers) receiverTriangles = last.shadowTriangles;
    if (selection == render::CasterSelection::FrustumBody) frustumTriangles = last.shadowTriangles;
  }
  std::printf("shadow-pass triangles, receivers / frustum B: %.3f\n",
              static_cast<double>(receiverTriangles) / static_cast<double>(std::max(1LL, frustumTriangles)));
  }
  // Blur cost per radius, and per method the shadow pass and shadow term (walkthrough start).
  std::printf("\nblur radius (px)  blur ms  (at the walkthrough start, lispsm 2048²)\n");
  for (double radius : {0.0, 1.0, 2.0, 4.0, 8.0, 16.0}) {
    render::FrameSettings settings;
    settings.blurRadius = radius;
    frame.render(start, 0.0, settings);
    double sum = 0.0;
    for (int f = 0; f < frames; ++f) sum += frame.render(start, 0.0, settings).passMs[FramePass::Blur];
    std::printf("%16.0f %8.2f\n", radius, sum / frames);
  }
  std::printf("\n%-15s %10s %10s\n", "method", "shadow ms", "term ms");
  for (shadows::ShadowMethod method :
       {shadows::ShadowMethod::Uniform, shadows::ShadowMethod::UniformStable, shadows::ShadowMethod::Lispsm,
        shadows::ShadowMethod::Tsm, shadows::ShadowMethod::TsmIterative}) {
    render::FrameSettings settings;
    settings.method = method;
    frame.render(start, 0.0, settings);
    double shadow = 0.0, term = 0.0;
    for (int f = 0; f < frames; ++f) {
      const render::FrameStats s = frame.render(start, 0.0, settings);
      shadow += s.passMs[FramePass::Shadow];
      term += s.passMs[FramePass::ShadowTerm];
    }
    std::printf("%-15s %10.2f %10.2f\n", std::string(shadows::kShadowMethodNames.name(method)).c_str(), shadow / frames, term / frames);
  }
  return 0;
}
