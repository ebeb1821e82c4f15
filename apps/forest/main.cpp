// forest — the command line of the forest engine (apps/forest/cli.hpp).
#include "cli.hpp"
#include "forest/core/heap.hpp"

int main(int argc, char** argv) {
  forest::keepFreedHeapMemory();  // frames reuse what the last frame freed (core/heap.hpp)
  forest::app::ForestCli cli;
  return cli.main(argc, argv);
}
