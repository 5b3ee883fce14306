# Fails when an object file needs the heap, exceptions or RTTI: cmake -DNM=nm -DOBJECTS="a.o;b.o" -P this-file.
# The proof of heap-freedom is what the linker would have to bring in, not a runtime assert.
foreach(object IN LISTS OBJECTS)
  execute_process(COMMAND "${NM}" -C -u "${object}" OUTPUT_VARIABLE undefined RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${NM} failed on ${object}")
  endif()
  # Whole symbol names after nm's "U ": a substring would also match e.g. __asan_stack_malloc_1.
  string(REGEX MATCHALL "U (malloc|calloc|realloc|free|_sbrk|operator new[^\n]*|operator delete[^\n]*|__cxa_throw|__cxa_allocate_exception|__cxa_begin_catch|__cxa_guard_acquire|__cxa_guard_release|__gxx_personality_v0|typeinfo[^\n]*|__dynamic_cast)\n"
         offending "${undefined}\n")
  if(offending)
    string(REPLACE ";" "\n" offending "${offending}")
    message(FATAL_ERROR "${object} needs heap/exception/RTTI symbols:\n${offending}")
  endif()
  message(STATUS "${object}: no heap, exception or RTTI symbol")
endforeach()
