// Reads a scene through the installed library and checks a value: proves headers, libraries and
// transitive dependencies of the package all resolve.
#include <forest/core/scene.hpp>
#include <forest/gl/context.hpp>

#include <cstdio>

int main() {
  const forest::Scene scene = forest::parseScene("[camera]\nfar = 500.0\n", "consumer.toml");
  if (scene.camera.far != 500.0) return 1;
  if (forest::gl::kBackendNames.parse("egl") != forest::gl::Backend::Egl) return 1;
  std::puts("consumer: ok");
  return 0;
}
