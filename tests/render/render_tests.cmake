# Tests of pnf/render.hpp and pnf/png.hpp, and the render and compare commands (via
# PNF_CLI_PATH; skipped when the tool is not built): included into the single test executable.
list(APPEND PNF_TEST_SOURCES
  ${PROJECT_SOURCE_DIR}/tests/render/render_test.cpp
  ${PROJECT_SOURCE_DIR}/tests/render/png_test.cpp
  ${PROJECT_SOURCE_DIR}/tests/render/render_cli_test.cpp)
