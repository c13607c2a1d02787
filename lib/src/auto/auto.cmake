# Sources of pnf::estimate_data and pnf::choose_filter_params (`pnf filter --auto`). Included by
# lib/CMakeLists.txt into the pnf target, which provides OpenMP, Eigen and the FLANN headers.
list(APPEND PNF_AUTO_SOURCES
  ${PROJECT_SOURCE_DIR}/lib/src/auto/auto_params.cpp)
