# Runs one fuzzer for SECONDS on a scratch copy of its seed corpus and of its REGRESSIONS folder
# (inputs that once crashed it, run first like any seed; the folder may be absent); any crash
# fails the test and leaves the input that caused it in WORK (add it to REGRESSIONS).
file(REMOVE_RECURSE "${WORK}")
file(MAKE_DIRECTORY "${WORK}/corpus")
file(GLOB seeds "${SEEDS}/*")
if(DEFINED REGRESSIONS)
  file(GLOB regressions "${REGRESSIONS}/*")
  list(APPEND seeds ${regressions})
endif()
file(COPY ${seeds} DESTINATION "${WORK}/corpus")
execute_process(
  COMMAND "${FUZZER}" -max_total_time=${SECONDS} -timeout=10 -rss_limit_mb=2048 -max_len=4096
          "-artifact_prefix=${WORK}/" "${WORK}/corpus"
  RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "fuzzer ${FUZZER} failed (${rc}); the input is in ${WORK}")
endif()
