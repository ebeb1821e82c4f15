// DESIGN §9: a steady-state frame allocates nothing on the heap. Every operator new of this test
// binary is counted while a frame renders (the GL driver's own mallocs are not: they are not this
// engine's); after a warm-up pass along the default walk, a second pass must make no allocation at
// all, in both the profiling and the GPU modes. FOREST_ALLOCATION_TRACE=1 prints a backtrace per
// allocation.
#include <execinfo.h>
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <new>

#include "forest/core/camera_path.hpp"
#include "forest/core/scene.hpp"
#include "forest/render/frame.hpp"
#include "gl_test_support.hpp"
#include "test_paths.hpp"

namespace {

std::atomic<bool> counting{false};
std::atomic<long> allocations{0};

void count() {
  if (!counting.load(std::memory_order_relaxed)) return;
  allocations.fetch_add(1, std::memory_order_relaxed);
  if (std::getenv("FOREST_ALLOCATION_TRACE") != nullptr) {
    counting = false;
    void* frames[24];
    const int n = backtrace(frames, 24);
    (void)!write(2, "--- allocation\n", 15);
    backtrace_symbols_fd(frames, n, 2);
    counting = true;
  }
}

void* allocate(std::size_t bytes, std::size_t alignment = 0) {
  count();
  if (alignment > alignof(std::max_align_t)) {
    const std::size_t rounded = (std::max<std::size_t>(bytes, 1) + alignment - 1) / alignment * alignment;
    return std::aligned_alloc(alignment, rounded);
  }
  return std::malloc(bytes == 0 ? 1 : bytes);
}

void* allocateOrThrow(std::size_t bytes, std::size_t alignment = 0) {
  if (void* p = allocate(bytes, alignment)) return p;
  throw std::bad_alloc();
}

}  // namespace

// Every replaceable form, all on malloc/free, so memory allocated by one form (in this binary or
// in a library, e.g. llvmpipe's LLVM) and freed by another always matches — also under ASan.
void* operator new(std::size_t bytes) { return allocateOrThrow(bytes); }
void* operator new[](std::size_t bytes) { return allocateOrThrow(bytes); }
void* operator new(std::size_t bytes, const std::nothrow_t&) noexcept { return allocate(bytes); }
void* operator new[](std::size_t bytes, const std::nothrow_t&) noexcept { return allocate(bytes); }
void* operator new(std::size_t bytes, std::align_val_t a) { return allocateOrThrow(bytes, static_cast<std::size_t>(a)); }
void* operator new[](std::size_t bytes, std::align_val_t a) { return allocateOrThrow(bytes, static_cast<std::size_t>(a)); }
void* operator new(std::size_t bytes, std::align_val_t a, const std::nothrow_t&) noexcept { return allocate(bytes, static_cast<std::size_t>(a)); }
void* operator new[](std::size_t bytes, std::align_val_t a, const std::nothrow_t&) noexcept { return allocate(bytes, static_cast<std::size_t>(a)); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept { std::free(p); }

namespace forest::test {
namespace {

constexpr double kFramesPerSecond = 2.5;

// The first `frames` frames of the default walk (data/paths/walk.toml over data/scenes/forest.toml,
// 320×180); returns the allocations made while rendering them (counted when `count`).
long allocationsAlongWalk(render::Frame& frame, const CameraPath& path, const render::FrameSettings& settings, int frames,
                          bool count) {
  long made = 0;
  frame.resetHistory();  // both passes start alike (a camera cut from the walk's end)
  for (int f = 0; f < frames; ++f) {
    const double time = path.startTime() + f / kFramesPerSecond;
    const Camera camera = frame.cameraAt(path.at(time), path.aboveGround());
    allocations = 0;
    counting = count;
    frame.render(camera, time, settings);
    counting = false;
    made += allocations;
    frame.takePassTimes();  // the caller's records, outside the frame
  }
  return made;
}

// Steady state = every list, pool and ring has reached the walk's high-water mark: the whole walk
// once as warm-up, then again from the same start, counted (2.5 frames per second of path time).
// The engine's, not the backend's: run on EGL only.
TEST_F(GlTest, SteadyStateFramesOfTheDefaultWalkAllocateNothing) {
  if (backendUnderTest() != "egl") GTEST_SKIP() << "the engine's allocations do not depend on the backend";
  const Scene scene = loadScene(std::string(FOREST_REPO_DATA) + "/scenes/forest.toml");
  const CameraPath path = CameraPath::load(std::string(FOREST_REPO_DATA) + "/paths/walk.toml");
  render::Frame frame(scene, 320, 180);
  // Under the sanitizers the first third of the walk, warmed up and counted the same way.
  const int frames = static_cast<int>(std::floor((path.endTime() - path.startTime()) * kFramesPerSecond / kSweepStride)) + 1;
  // Both timing modes with one map, and the GPU's modes with four cascades (per-slice lists, the
  // nearest-depth ring).
  struct Mode {
    gl::TimingMode timing;
    culling::QueryMode queries;
    int cascades;
  };
  for (const Mode& mode : {Mode{gl::TimingMode::Profiling, culling::QueryMode::Deterministic, 1},
                           Mode{gl::TimingMode::GpuQueries, culling::QueryMode::Async, 1},
                           Mode{gl::TimingMode::GpuQueries, culling::QueryMode::Async, 4}}) {
    render::FrameSettings settings;
    settings.blurRadius = 3.0;
    settings.timing = mode.timing;
    settings.queries = mode.queries;
    settings.cascades = mode.cascades;
    SCOPED_TRACE(std::string(gl::kTimingModeNames.name(mode.timing)) + " timing, " + std::to_string(mode.cascades) + " cascade(s)");
    allocationsAlongWalk(frame, path, settings, frames, false);
    EXPECT_EQ(allocationsAlongWalk(frame, path, settings, frames, true), 0) << "heap allocations in " << frames << " frames";
  }
}

}  // namespace
}  // namespace forest::test
