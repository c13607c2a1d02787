# Sources of pnf::estimate_data (the measurements) and pnf::choose_filter_params (the rule of
# `pnf filter --auto`). Included by lib/CMakeLists.txt into the pnf target, which provides OpenMP
# and Eigen; neighbour searches go through host/spatial.
list(APPEND PNF_AUTO_SOURCES
  ${PROJECT_SOURCE_DIR}/lib/src/auto/estimate_data.cpp
  ${PROJECT_SOURCE_DIR}/lib/src/auto/sample_fit.cpp
  ${PROJECT_SOURCE_DIR}/lib/src/auto/sample_neighbourhoods.cpp
  ${PROJECT_SOURCE_DIR}/lib/src/auto/choose_filter_params.cpp
  ${PROJECT_SOURCE_DIR}/lib/src/auto/crease_evidence.cpp
  ${PROJECT_SOURCE_DIR}/lib/src/auto/surface_judge.cpp
  ${PROJECT_SOURCE_DIR}/lib/src/auto/neighbour_normal_noise.cpp
  ${PROJECT_SOURCE_DIR}/lib/src/auto/stein_risk.cpp
  ${PROJECT_SOURCE_DIR}/lib/src/auto/improve_normals_auto.cpp)
