// frame_bench: per-pass time and triangles of the frame for the default forest at the walkthrough
// start, with shadow casters chosen from the visible receivers, from the frustum's focus body B,
// or all objects.   build/release/bench/frame_bench [--gl=auto|egl|osmesa] [--frames N]
#include <cstdio>
#include <string>

#include "forest/core/resources.hpp"
#include "forest/gl/context.hpp"
#include "forest/render/frame.hpp"

int main(int argc, char** argv) {
  using namespace forest;
  std::string backend = "auto";
  int frames = 5;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a.rfind("--gl=", 0) == 0) backend = a.substr(5);
    else if (a == "--frames" && i + 1 < argc) frames = std::stoi(argv[++i]);
    else {
      std::fprintf(stderr, "usage: frame_bench [--gl=auto|egl|osmesa] [--frames N]\n");
      return 2;
    }
  }
  const Scene scene = loadScene(resourceDirectory("data") / "scenes" / "forest.toml");
  gl::ContextOptions contextOptions;
  contextOptions.backend = gl::parseBackend(backend);
  auto context = gl::createContext(contextOptions);
  std::printf("%s\n", gl::describe(context->info()).c_str());
  render::Frame frame(scene, scene.render.width, scene.render.height);
  const Camera camera = frame.startCamera();
  std::printf("%dx%d, lispsm 2048², CHC, %d frames each (after one warm-up)\n\n", frame.width(), frame.height(), frames);
  std::printf("%-13s %8s %8s %8s %8s %8s | %9s %10s %8s %10s\n", "casters", "geom ms", "setup ms", "shadow", "term ms",
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
      sum.geometryMs += last.geometryMs;
      sum.shadowSetupMs += last.shadowSetupMs;
      sum.shadowMs += last.shadowMs;
      sum.shadowTermMs += last.shadowTermMs;
      sum.lightingMs += last.lightingMs;
    }
    std::printf("%-13s %8.2f %8.2f %8.2f %8.2f %8.2f | %9d %10lld %8d %10lld\n",
                std::string(render::casterSelectionName(selection)).c_str(), sum.geometryMs / frames,
                sum.shadowSetupMs / frames, sum.shadowMs / frames, sum.shadowTermMs / frames, sum.lightingMs / frames,
                last.visibleObjects, last.geometryTriangles, last.casterObjects, last.shadowTriangles);
    if (selection == render::CasterSelection::Receivers) receiverTriangles = last.shadowTriangles;
    if (selection == render::CasterSelection::FrustumBody) frustumTriangles = last.shadowTriangles;
  }
  std::printf("\nshadow-pass triangles, receivers / frustum B: %.3f\n",
              static_cast<double>(receiverTriangles) / static_cast<double>(std::max(1LL, frustumTriangles)));
  return 0;
}
