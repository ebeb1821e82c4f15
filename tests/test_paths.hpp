#pragma once
// Where the tests find their data, the repository's data, their output folder and the forest
// program. The absolute paths are compiled into test_paths.cpp alone: no other test source carries
// one on its command line, so ccache (CCACHE_BASEDIR, CMakeLists.txt) reuses their objects from
// any clone of the repository.

namespace forest::test {
const char* testDataDir();    // tests/data
const char* testOutputDir();  // <build>/test-output
const char* repoDataDir();    // data/
const char* forestProgram();  // the forest executable
}  // namespace forest::test

#define FOREST_TEST_DATA (::forest::test::testDataDir())
#define FOREST_TEST_OUTPUT (::forest::test::testOutputDir())
#define FOREST_REPO_DATA (::forest::test::repoDataDir())
#define FOREST_EXE (::forest::test::forestProgram())
