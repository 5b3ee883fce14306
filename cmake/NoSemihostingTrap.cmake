# cmake -DOBJDUMP=<arm-none-eabi-objdump> -DFILES=<object or ELF>[;...] -P NoSemihostingTrap.cmake
# Fails if the code of FILES holds a semihosting trap (`bkpt 0xab`): built without semihosting (LASHID_SEMIHOSTING
# OFF), an image must run on a board without a debugger, where that trap faults.
foreach(file IN LISTS FILES)
  execute_process(COMMAND "${OBJDUMP}" -d "${file}" OUTPUT_VARIABLE listing RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0 OR NOT listing MATCHES "<[^>]+>:")
    message(FATAL_ERROR "${OBJDUMP} -d ${file} failed or listed no code (rc ${rc})")
  endif()
  string(REGEX MATCHALL "[^\n]*bkpt[^\n]*" traps "${listing}")
  if(traps)
    string(REPLACE ";" "\n" traps "${traps}")
    message(FATAL_ERROR "${file} holds semihosting traps:\n${traps}")
  endif()
  message(STATUS "${file}: no bkpt")
endforeach()
