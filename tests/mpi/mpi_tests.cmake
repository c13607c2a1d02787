# pnf::mpi under mpirun: the library test on P = 1..4 ranks (oversubscribed on small machines;
# Open MPI refuses root without the two variables). Included from tests/CMakeLists.txt when
# PNF_WITH_MPI is on.
add_executable(pnf_mpi_tests ${PROJECT_SOURCE_DIR}/tests/mpi/mpi_test.cpp
  ${PROJECT_SOURCE_DIR}/tests/mpi/filter_file_test.cpp)
target_include_directories(pnf_mpi_tests PRIVATE ${PROJECT_SOURCE_DIR}/tests ${PROJECT_SOURCE_DIR}/lib/src ${PROJECT_SOURCE_DIR}/host
  ${PROJECT_SOURCE_DIR}/lib/src/mpi)
target_link_libraries(pnf_mpi_tests PRIVATE pnf_mpi GTest::gtest)
set(PNF_MPI_TEST_ENVIRONMENT OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_NUM_THREADS=1)
if(PNF_SANITIZE)
  # Open MPI's components are dlopened and unloaded before exit, so LeakSanitizer reports their
  # allocations with no frame a suppression could name. Leaks stay checked everywhere else (the
  # whole non-MPI suite, pnf's own code included); ASan and UBSan still check these runs.
  list(APPEND PNF_MPI_TEST_ENVIRONMENT "ASAN_OPTIONS=detect_leaks=0:abort_on_error=1")
endif()
# About 40-50 s a rank count in Release on this project's 2-core machine; under the sanitizers
# fifteen times that (each judged --auto run on the house 45-155 s), which ran past a 900 s limit in
# CI (2026-12-07: np 1 and 2 on a slower machine). So there each rank count's run is cut into
# GoogleTest shards, one ctest entry each (mpirun hands GTEST_TOTAL_SHARDS and GTEST_SHARD_INDEX to
# every rank, so all ranks run the same tests), and the MpiAuto suite runs at P = 1 (no halos) and 3
# (uneven partitions, halos): the sanitizers look for memory and undefined-behaviour errors, which
# P = 2 and 4 reach through the same code, while the Release suite still compares every P = 1..4
# with one process.
if(PNF_SANITIZE)
  set(PNF_MPI_LIBRARY_SHARDS 4)
  set(PNF_MPI_LIBRARY_TIMEOUT 900)
else()
  set(PNF_MPI_LIBRARY_SHARDS 1)
  set(PNF_MPI_LIBRARY_TIMEOUT 300)
endif()
math(EXPR last_shard "${PNF_MPI_LIBRARY_SHARDS} - 1")
foreach(ranks 1 2 3 4)
  set(filter "*")
  if(PNF_SANITIZE AND (ranks EQUAL 2 OR ranks EQUAL 4))
    set(filter "-MpiAuto.*")
  endif()
  foreach(shard RANGE ${last_shard})
    set(name mpi_library_np${ranks})
    if(PNF_MPI_LIBRARY_SHARDS GREATER 1)
      string(APPEND name "_shard${shard}")
    endif()
    add_test(NAME ${name}
      COMMAND ${MPIEXEC_EXECUTABLE} --oversubscribe ${MPIEXEC_NUMPROC_FLAG} ${ranks} $<TARGET_FILE:pnf_mpi_tests>
              --gtest_filter=${filter})
    set_tests_properties(${name} PROPERTIES TIMEOUT ${PNF_MPI_LIBRARY_TIMEOUT}
      ENVIRONMENT "${PNF_MPI_TEST_ENVIRONMENT};GTEST_TOTAL_SHARDS=${PNF_MPI_LIBRARY_SHARDS};GTEST_SHARD_INDEX=${shard}")
  endforeach()
endforeach()

# The command line under mpirun (needs the pnf tool and python3).
if(TARGET pnf_cli)
  find_package(Python3 COMPONENTS Interpreter)
  if(Python3_FOUND)
    add_test(NAME mpi_cli
      COMMAND bash ${PROJECT_SOURCE_DIR}/tests/mpi/cli_mpi_test.sh $<TARGET_FILE:pnf_cli> ${MPIEXEC_EXECUTABLE}
              ${CMAKE_CURRENT_BINARY_DIR}/mpi_cli_work)
    set_tests_properties(mpi_cli PROPERTIES TIMEOUT 600 ENVIRONMENT "${PNF_MPI_TEST_ENVIRONMENT}")
    # Every filter flag under mpirun, OUT in every format for P = 1..4, a kill during the write.
    foreach(part flags formats kill)
      add_test(NAME mpi_cli_${part}
        COMMAND bash ${PROJECT_SOURCE_DIR}/tests/mpi/cli_mpi_${part}_test.sh $<TARGET_FILE:pnf_cli>
                ${MPIEXEC_EXECUTABLE} ${CMAKE_CURRENT_BINARY_DIR}/mpi_cli_${part}_work)
      set_tests_properties(mpi_cli_${part} PROPERTIES TIMEOUT 300 ENVIRONMENT "${PNF_MPI_TEST_ENVIRONMENT}")
    endforeach()
  endif()
endif()
