# Sources of pnf::estimate_normals (PCA normals with viewpoint, outward or mst orientation).
# Included by lib/CMakeLists.txt into the pnf target, which provides OpenMP, Eigen and the FLANN
# headers. FLANN's kd-tree carries virtual save/load members that call LZ4, so the target must
# link liblz4 even though nothing here serialises an index.
list(APPEND PNF_ESTIMATE_SOURCES
  ${PROJECT_SOURCE_DIR}/lib/src/estimate/estimate_normals.cpp
  ${PROJECT_SOURCE_DIR}/lib/src/estimate/orient_normals.cpp
  ${PROJECT_SOURCE_DIR}/lib/src/estimate/orient_normals.hpp)
