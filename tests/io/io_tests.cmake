# Tests of pnf/point_file.hpp: included into the single test executable. They include
# ply_test_files.hpp from this folder, and read ../shared/data via PNF_SHARED_DATA_DIR.
list(APPEND PNF_TEST_SOURCES
  ${PROJECT_SOURCE_DIR}/tests/io/point_file_test.cpp
  ${PROJECT_SOURCE_DIR}/tests/io/point_file_encodings_test.cpp
  ${PROJECT_SOURCE_DIR}/tests/io/text_formats_test.cpp
  ${PROJECT_SOURCE_DIR}/tests/io/atomic_write_test.cpp
  ${PROJECT_SOURCE_DIR}/tests/io/point_file_errors_test.cpp
  ${PROJECT_SOURCE_DIR}/tests/io/point_file_shared_data_test.cpp
  ${PROJECT_SOURCE_DIR}/tests/io/pcd_test.cpp
  ${PROJECT_SOURCE_DIR}/tests/io/pcd_invalid_points_test.cpp
  ${PROJECT_SOURCE_DIR}/tests/io/pcd_errors_test.cpp
  ${PROJECT_SOURCE_DIR}/tests/io/pcd_shared_data_test.cpp)
