# Tests of pnf::estimate_data, pnf::choose_filter_params and `pnf filter --auto` / --stop-change:
# included into the single test executable (the CLI cases skip when PNF_CLI_PATH is empty).
list(APPEND PNF_TEST_SOURCES
  ${PROJECT_SOURCE_DIR}/tests/auto/auto_params_test.cpp)
list(APPEND PNF_TEST_SOURCES
  ${PROJECT_SOURCE_DIR}/tests/auto/auto_params_creases_test.cpp)
