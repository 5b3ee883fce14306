# Runs COMMAND (a list) and fails unless it exits with EXPECTED_CODE and its output (stdout and stderr) contains
# EXPECTED_OUTPUT: cmake -DCOMMAND="a;b" -DEXPECTED_CODE=N -DEXPECTED_OUTPUT=text -P expect_exit.cmake.
# CTest itself can only tell zero from non-zero, and a crash of the emulator is non-zero too.
execute_process(COMMAND ${COMMAND} OUTPUT_VARIABLE out ERROR_VARIABLE err RESULT_VARIABLE code TIMEOUT 50)
message("${out}${err}")
if(NOT code STREQUAL "${EXPECTED_CODE}")
  message(FATAL_ERROR "exit ${code}, expected ${EXPECTED_CODE}")
endif()
string(FIND "${out}${err}" "${EXPECTED_OUTPUT}" at)
if(at EQUAL -1)
  message(FATAL_ERROR "the output does not contain '${EXPECTED_OUTPUT}'")
endif()
