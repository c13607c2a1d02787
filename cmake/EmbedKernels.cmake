# pnf_embed_kernels(OUTPUT <file.cpp> SOURCES <files...>)
# Writes a C++ source with each kernel file as a byte array (no string-literal length limits),
# looked up by file name at run time through host/embedded_kernels.hpp. Runs at build time and
# re-runs when any kernel file changes; the output lives in the build tree only.
set(PNF_EMBED_SCRIPT "${CMAKE_CURRENT_LIST_DIR}/embed_files.cmake")

function(pnf_embed_kernels)
  cmake_parse_arguments(ARG "" "OUTPUT" "SOURCES" ${ARGN})
  add_custom_command(
    OUTPUT "${ARG_OUTPUT}"
    COMMAND "${CMAKE_COMMAND}" "-DOUTPUT=${ARG_OUTPUT}" "-DSOURCES=${ARG_SOURCES}"
            -P "${PNF_EMBED_SCRIPT}"
    DEPENDS ${ARG_SOURCES} "${PNF_EMBED_SCRIPT}"
    COMMENT "Embedding OpenCL kernels"
    VERBATIM)
endfunction()
