# Sources of pnf::estimate_normals (PCA normals with viewpoint, outward or mst orientation).
# Included by lib/CMakeLists.txt into the pnf target, which provides OpenMP and Eigen; the k
# nearest come from host/spatial (the one FLANN user).
list(APPEND PNF_ESTIMATE_SOURCES
  ${PROJECT_SOURCE_DIR}/lib/src/estimate/estimate_normals.cpp
  ${PROJECT_SOURCE_DIR}/lib/src/estimate/orient_normals.cpp
  ${PROJECT_SOURCE_DIR}/lib/src/estimate/orient_normals.hpp)
