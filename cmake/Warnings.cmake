# Project warnings as an interface target: link `lashid::warnings` to opt in.
option(LASHID_WARNINGS_AS_ERRORS "Treat warnings as errors" ON)
add_library(lashid_warnings INTERFACE)
add_library(lashid::warnings ALIAS lashid_warnings)
target_compile_options(lashid_warnings INTERFACE
  $<$<CXX_COMPILER_ID:GNU,Clang>:
    -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wsign-conversion
    -Wdouble-promotion -Wnon-virtual-dtor -Wold-style-cast -Wcast-align
    -Woverloaded-virtual -Wimplicit-fallthrough
    -Wmisleading-indentation -Wformat=2>
  # GCC only (cmake_template's set): identical branches or conditions, && / || on non-booleans, casts to the same
  # type, virtual functions overridden without `override`.
  $<$<CXX_COMPILER_ID:GNU>:
    -Wduplicated-branches -Wduplicated-cond -Wlogical-op -Wuseless-cast -Wsuggest-override>
  # GCC 12 at -O2 reports -Wnull-dereference inside libstdc++'s istreambuf_iterator (false positive): Clang only.
  $<$<CXX_COMPILER_ID:Clang>:-Wnull-dereference>
  $<$<AND:$<CXX_COMPILER_ID:GNU,Clang>,$<BOOL:${LASHID_WARNINGS_AS_ERRORS}>>:-Werror>)
