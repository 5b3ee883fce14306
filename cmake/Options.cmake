# Project build options as an interface target: link `lashid::options` to opt in (every host library, test and
# the tool do; the freestanding probe and the firmware do not).
#
# LASHID_SANITIZERS: a list such as "address;undefined", applied to compile and link of the targets that opt in,
# with -fno-sanitize-recover=all so that the first report fails the test.
set(LASHID_SANITIZERS "" CACHE STRING "Sanitizers for the host targets, e.g. address;undefined (empty: none)")

add_library(lashid_options INTERFACE)
add_library(lashid::options ALIAS lashid_options)
if(LASHID_SANITIZERS)
  if(CMAKE_CROSSCOMPILING)
    message(FATAL_ERROR "LASHID_SANITIZERS is for host builds; the Cortex-M runtime has no sanitizer support")
  endif()
  list(JOIN LASHID_SANITIZERS "," sanitizers)
  target_compile_options(lashid_options INTERFACE -fsanitize=${sanitizers} -fno-sanitize-recover=all
                                                  -fno-omit-frame-pointer)
  target_link_options(lashid_options INTERFACE -fsanitize=${sanitizers})
endif()
