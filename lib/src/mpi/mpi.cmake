# pnf::mpi — the filter across the ranks of an MPI job (pnf/mpi.hpp). A target of its own, so
# that pnf::pnf never depends on MPI. Uses the engine's internals (lib/src, host, kernels).
add_library(pnf_mpi
  ${PROJECT_SOURCE_DIR}/lib/src/mpi/agreement.cpp
  ${PROJECT_SOURCE_DIR}/lib/src/mpi/choose_filter_params_mpi.cpp
  ${PROJECT_SOURCE_DIR}/lib/src/mpi/device_choice.cpp
  ${PROJECT_SOURCE_DIR}/lib/src/mpi/filter_file_mpi.cpp
  ${PROJECT_SOURCE_DIR}/lib/src/mpi/halo.cpp
  ${PROJECT_SOURCE_DIR}/lib/src/mpi/improve_normals.cpp
  ${PROJECT_SOURCE_DIR}/lib/src/mpi/improve_normals_auto_mpi.cpp
  ${PROJECT_SOURCE_DIR}/lib/src/mpi/mean_radius_mpi.cpp
  ${PROJECT_SOURCE_DIR}/lib/src/mpi/partition.cpp
  ${PROJECT_SOURCE_DIR}/lib/src/mpi/ply_slices.cpp
  ${PROJECT_SOURCE_DIR}/lib/src/mpi/rank_cloud_check.cpp
  ${PROJECT_SOURCE_DIR}/lib/src/mpi/staged_output.cpp)
add_library(pnf::mpi ALIAS pnf_mpi)
set_target_properties(pnf_mpi PROPERTIES POSITION_INDEPENDENT_CODE ON EXPORT_NAME mpi)
target_include_directories(pnf_mpi PRIVATE
  ${PROJECT_SOURCE_DIR}/host
  ${PROJECT_SOURCE_DIR}/kernels
  ${PROJECT_SOURCE_DIR}/lib/src
  ${PROJECT_SOURCE_DIR}/lib/src/io
  ${FLANN_INCLUDE_DIR})
target_link_libraries(pnf_mpi PUBLIC pnf MPI::MPI_CXX PRIVATE lz4)
target_compile_options(pnf_mpi PRIVATE -Wall -Wextra)
