# Fails when an object file needs the heap, exceptions or RTTI: cmake -DNM=nm -DOBJECTS="a.o;b.o" -P this-file.
# The proof of heap-freedom is what the linker would have to bring in, not a runtime assert.
foreach(object IN LISTS OBJECTS)
  execute_process(COMMAND "${NM}" -C -u "${object}" OUTPUT_VARIABLE undefined RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${NM} failed on ${object}")
  endif()
  string(REGEX MATCHALL "[^\n]*(malloc|calloc|realloc|free|_sbrk|operator new|operator delete|__cxa_throw|__cxa_allocate_exception|__cxa_begin_catch|__gxx_personality|typeinfo|__dynamic_cast)[^\n]*"
         offending "${undefined}")
  if(offending)
    string(REPLACE ";" "\n" offending "${offending}")
    message(FATAL_ERROR "${object} needs heap/exception/RTTI symbols:\n${offending}")
  endif()
  message(STATUS "${object}: no heap, exception or RTTI symbol")
endforeach()
