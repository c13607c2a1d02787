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
  ${PROJECT_SOURCE_DIR}/lib/src/auto/quadric_moments.cpp
  ${PROJECT_SOURCE_DIR}/lib/src/auto/vector_exp.cpp
  ${PROJECT_SOURCE_DIR}/lib/src/auto/neighbour_normal_noise.cpp
  ${PROJECT_SOURCE_DIR}/lib/src/auto/stein_risk.cpp
  ${PROJECT_SOURCE_DIR}/lib/src/auto/held_out_planes.cpp
  ${PROJECT_SOURCE_DIR}/lib/src/auto/improve_normals_auto.cpp)
# vector_exp's wide steps, each built with its instruction set and run only where the CPU has it.
if(CMAKE_SYSTEM_PROCESSOR MATCHES "x86_64|AMD64")
  set(vector_exp_avx512 ${PROJECT_SOURCE_DIR}/lib/src/auto/vector_exp_avx512.cpp)
  set(vector_exp_avx ${PROJECT_SOURCE_DIR}/lib/src/auto/vector_exp_avx.cpp)
  list(APPEND PNF_AUTO_SOURCES ${vector_exp_avx512} ${vector_exp_avx})
  set_source_files_properties(${vector_exp_avx512} PROPERTIES COMPILE_OPTIONS -mavx512f)
  set_source_files_properties(${vector_exp_avx} PROPERTIES COMPILE_OPTIONS -mavx)
endif()
