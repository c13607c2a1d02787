# Installs headers, the libraries and a CMake package: find_package(pnf CONFIG) + pnf::pnf, and
# pnf::mpi when built with MPI.

include(CMakePackageConfigHelpers)

set(pnf_installed_targets pnf)
if(PNF_WITH_MPI)
  list(APPEND pnf_installed_targets pnf_mpi)
endif()
install(TARGETS ${pnf_installed_targets} EXPORT pnfTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/lib/include/pnf DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(EXPORT pnfTargets NAMESPACE pnf:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/pnf)

configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/pnfConfig.cmake.in
  ${CMAKE_CURRENT_BINARY_DIR}/pnfConfig.cmake
  INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/pnf)
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/pnfConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/pnfConfig.cmake ${CMAKE_CURRENT_BINARY_DIR}/pnfConfigVersion.cmake
  DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/pnf)
