# A test that a command fails in the way it should: runs COMMAND (a list) and fails unless it exits with
# EXPECTED_CODE and its output (stdout and stderr) matches the regular expression EXPECTED_OUTPUT.
#   cmake -DCOMMAND="a;b" -DEXPECTED_CODE=N -DEXPECTED_OUTPUT=regex -P ExpectExit.cmake
# CTest alone checks either the exit code (WILL_FAIL: any failure, a crash too) or the output
# (PASS_REGULAR_EXPRESSION, which ignores the exit code), not both. Users: the stack-overflow image
# (firmware/smoke), the symbol check's and the layering check's refusals (tests/).
execute_process(COMMAND ${COMMAND} OUTPUT_VARIABLE out ERROR_VARIABLE err RESULT_VARIABLE code TIMEOUT 50)
message("${out}${err}")
if(NOT code STREQUAL "${EXPECTED_CODE}")
  message(FATAL_ERROR "exit ${code}, expected ${EXPECTED_CODE}")
endif()
if(NOT "${out}${err}" MATCHES "${EXPECTED_OUTPUT}")
  message(FATAL_ERROR "the output does not match '${EXPECTED_OUTPUT}'")
endif()
