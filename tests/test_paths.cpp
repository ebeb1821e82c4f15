#include "test_paths.hpp"

namespace forest::test {
const char* testDataDir() { return FOREST_TEST_DATA_PATH; }
const char* testOutputDir() { return FOREST_TEST_OUTPUT_PATH; }
const char* repoDataDir() { return FOREST_REPO_DATA_PATH; }
const char* forestProgram() { return FOREST_EXE_PATH; }
}  // namespace forest::test
