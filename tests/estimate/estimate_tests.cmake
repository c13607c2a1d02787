# Tests of pnf::estimate_normals, included into the single test executable. The thread-count
# determinism test needs the executable compiled with OpenMP (it skips itself otherwise).
list(APPEND PNF_TEST_SOURCES
  ${PROJECT_SOURCE_DIR}/tests/estimate/estimate_normals_test.cpp
  ${PROJECT_SOURCE_DIR}/tests/estimate/estimate_normals_input_test.cpp)
