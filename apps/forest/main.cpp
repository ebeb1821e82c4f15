// forest — the command line of the forest engine (apps/forest/cli.hpp).
#include "cli.hpp"

int main(int argc, char** argv) {
  forest::app::ForestCli cli;
  return cli.main(argc, argv);
}
