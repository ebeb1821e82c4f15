#pragma once
// The reference frame: a fixed GL workload that `forest budget` times on the machine it runs on, so
// that a budget can state its limits in reference frames instead of milliseconds and one file
// serves a laptop, CI and a 2-core software renderer. It does what a frame of the engine does,
// without any of the engine's code (an engine that gets slower still shows in its ratio): a
// 256 × 256-cell heightfield (131 072 triangles, depth-tested) and three full-screen passes of 16
// texel reads each, at the run's size, timed from the first call to glFinish.
namespace forest::app {

// The median over `repeats` timings (after two untimed ones), in milliseconds. Needs a current GL
// context of its own (the state it leaves is not the engine's).
double measureReferenceFrameMs(int width, int height, int repeats = 9);

}  // namespace forest::app
