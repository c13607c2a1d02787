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
# About 25-30 s a rank count in Release on this project's 2-core machine; under the sanitizers ten
# times that (each judged --auto run on the house 60-105 s), which reached 298-300 s of a 300 s
# limit in CI (2026-12-06), so there the suite's own limit of 900 s.
if(PNF_SANITIZE)
  set(PNF_MPI_LIBRARY_TIMEOUT 900)
else()
  set(PNF_MPI_LIBRARY_TIMEOUT 300)
endif()
foreach(ranks 1 2 3 4)
  add_test(NAME mpi_library_np${ranks}
    COMMAND ${MPIEXEC_EXECUTABLE} --oversubscribe ${MPIEXEC_NUMPROC_FLAG} ${ranks} $<TARGET_FILE:pnf_mpi_tests>)
  set_tests_properties(mpi_library_np${ranks} PROPERTIES TIMEOUT ${PNF_MPI_LIBRARY_TIMEOUT}
                                                         ENVIRONMENT "${PNF_MPI_TEST_ENVIRONMENT}")
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
