# Tests of the pnf command-line tool: included into the single test executable. They run the
# built binary named by PNF_CLI_PATH (skipped when it is empty, i.e. PNF_BUILD_TOOLS is off) and
# read ../shared/data via PNF_SHARED_DATA_DIR.
list(APPEND PNF_TEST_SOURCES
  ${PROJECT_SOURCE_DIR}/tests/cli/cli_test.cpp
  ${PROJECT_SOURCE_DIR}/tests/cli/cli_commands_test.cpp
  ${PROJECT_SOURCE_DIR}/tests/cli/cli_options_test.cpp
  ${PROJECT_SOURCE_DIR}/tests/cli/cli_errors_test.cpp
  ${PROJECT_SOURCE_DIR}/tests/cli/cli_spacing_test.cpp)
