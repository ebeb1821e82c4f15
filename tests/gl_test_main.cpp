// main() of gl_tests: picks the backend from --gl=<name> (required) and creates its context.
#include <cstring>
#include <iostream>
#include <memory>

#include "forest/core/heap.hpp"
#include "forest/core/log.hpp"
#include "gl_test_support.hpp"

namespace forest::test {
namespace {
std::string gBackend;
std::unique_ptr<gl::Context> gContext;
}  // namespace

const std::string& backendUnderTest() { return gBackend; }

gl::Context& context() {
  if (!gContext) {
    gl::ContextOptions options;
    options.backend = gl::kBackendNames.parse(gBackend);
    options.visible = false;
    gContext = gl::createContext(options);
    std::cout << "[gl_tests] " << gl::describe(gContext->info()) << std::endl;
  }
  return *gContext;
}

}  // namespace forest::test

int main(int argc, char** argv) {
  forest::keepFreedHeapMemory();  // as the forest program does (core/heap.hpp)
  ::testing::InitGoogleTest(&argc, argv);
  for (int i = 1; i < argc; ++i) {
    if (std::strncmp(argv[i], "--gl=", 5) == 0) forest::test::gBackend = argv[i] + 5;
  }
  if (forest::test::gBackend.empty()) {
    std::cerr << "gl_tests: pass --gl=egl|osmesa|window\n";
    return 2;
  }
  try {
    forest::test::context();  // a backend that cannot make its context fails the run, loudly
  } catch (const std::exception& e) {
    std::cerr << "gl_tests: cannot create the " << forest::test::gBackend << " context: " << e.what() << "\n";
    return 1;
  }
  const int result = RUN_ALL_TESTS();
  forest::test::gContext.reset();
  return result;
}
