# Tests of the pnf command-line tool: included into the single test executable. They run the
# built binary named by PNF_CLI_PATH (skipped when it is empty, i.e. PNF_BUILD_TOOLS is off) and
# read ../shared/data via PNF_SHARED_DATA_DIR; progress_text_test compiles the tool's progress
# display (tools/pnf/progress_text.cpp) in.
list(APPEND PNF_TEST_SOURCES
  ${PROJECT_SOURCE_DIR}/tests/cli/cli_test.cpp
  ${PROJECT_SOURCE_DIR}/tests/cli/cli_commands_test.cpp
  ${PROJECT_SOURCE_DIR}/tests/cli/cli_options_test.cpp
  ${PROJECT_SOURCE_DIR}/tests/cli/cli_errors_test.cpp
  ${PROJECT_SOURCE_DIR}/tests/cli/cli_spacing_test.cpp
  ${PROJECT_SOURCE_DIR}/tests/cli/progress_text_test.cpp
  ${PROJECT_SOURCE_DIR}/tools/pnf/progress_text.cpp)
set_source_files_properties(${PROJECT_SOURCE_DIR}/tests/cli/progress_text_test.cpp
  PROPERTIES INCLUDE_DIRECTORIES ${PROJECT_SOURCE_DIR}/tools/pnf)

# scripts/demo.sh builds the pnf command alone (stubs stand in for cmake and the tool).
add_test(NAME demo_script_builds_only_the_tool
  COMMAND bash ${PROJECT_SOURCE_DIR}/tests/cli/demo_script_test.sh ${PROJECT_SOURCE_DIR})
