#pragma once
// Command-line flags shared by the GL benchmarks, and their context: --gl=NAME, --frames N,
// --width W, --height H. A bad flag prints the usage and exits with 2.
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>

#include "forest/core/heap.hpp"
#include "forest/gl/context.hpp"

namespace forest::bench {

struct BenchArgs {
  std::string backend = "auto";
  int frames = 5;
  int width = 1280;
  int height = 720;
};

inline BenchArgs parseBenchArgs(int argc, char** argv, const char* name, BenchArgs defaults = {}) {
  BenchArgs a = defaults;
  for (int i = 1; i < argc; ++i) {
    const std::string flag = argv[i];
    const bool hasValue = i + 1 < argc;
    try {
      if (flag.rfind("--gl=", 0) == 0) a.backend = flag.substr(5);
      else if (flag == "--frames" && hasValue) a.frames = std::stoi(argv[++i]);
      else if (flag == "--width" && hasValue) a.width = std::stoi(argv[++i]);
      else if (flag == "--height" && hasValue) a.height = std::stoi(argv[++i]);
      else throw std::invalid_argument(flag);
    } catch (const std::exception&) {
      std::fprintf(stderr, "usage: %s [--gl=auto|egl|osmesa] [--frames N] [--width W --height H]\n", name);
      std::exit(2);
    }
  }
  if (a.frames < 1 || a.width < 16 || a.height < 16) {
    std::fprintf(stderr, "%s: --frames must be >= 1, --width and --height >= 16\n", name);
    std::exit(2);
  }
  return a;
}

// The GL context for the benchmark; prints which device it got.
inline std::unique_ptr<gl::Context> benchContext(const BenchArgs& args) {
  keepFreedHeapMemory();  // as the forest program does: frames reuse freed memory (core/heap.hpp)
  gl::ContextOptions options;
  options.backend = gl::kBackendNames.parse(args.backend);
  auto context = gl::createContext(options);
  std::printf("%s\n", gl::describe(context->info()).c_str());
  return context;
}

}  // namespace forest::bench
