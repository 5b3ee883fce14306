# The worst-case stack depth of a Cortex-M image, proved at build time (test <image>_stack_fits, cmake/Firmware.cmake;
# docs/firmware.md, "Stack"). Fails on anything it cannot bound, and when the bound exceeds the reserved stack.
#
#   cmake -DELF=<elf> -DNM=<nm> -DOBJDUMP=<objdump> -DOBJCOPY=<objcopy> -DOBJECTS=<the image's objects>
#         -DEXCEPTION_FRAME=<B> [-DINDIRECT=<caller>=<section>[+<section>...];...] [-DFAULT_ROOTS=<handler>;...]
#         -P StackDepth.cmake
#
# The graph. Each object was compiled with -fcallgraph-info=su: GCC writes <object>.ci (VCG text) with every function
# it emitted, its frame in bytes (the number -fstack-usage gives: saved registers, locals, spills) and its calls
# after inlining, an indirect one as "__indirect_call". Code without a .ci (newlib, libgcc: memcpy, sqrtf, the
# soft-float routines) is read from the image's machine code (objdump -d): the frame is the sum of its pushes,
# vpushes, `sub sp, #N` and pre-decrementing stores to sp (each runs at most once per call in such code, so the sum
# bounds it), checked against GCC's number on every function GCC compiled. The machine code's direct calls (bl, and
# b/b.w to another function: a tail call counted as a call, an over-estimate) are added to every function's edges,
# so that a call the compiler did not see (a naked handler's branch, inline assembly) is not missed; so is an edge
# into the next symbol from every function whose last instruction is not an unconditional branch or return (code
# that runs on into it, as libgcc's __aeabi_dsub into __adddf3; after a call that does not return, an over-estimate).
#
# It fails, naming the function, on: recursion (a cycle); a frame GCC calls "dynamic" (alloca, a VLA); a stack
# pointer set from a register or memory (mov sp, msr msp, sub sp, rN) anywhere but in a root (the reset and fault
# handlers set it on purpose); a callee with no frame size; an object without a .ci; an indirect call that INDIRECT
# does not resolve. INDIRECT names, per caller, the sections whose words are the only targets of its indirect calls:
# lashid_cortex_m_start calls the static constructors of .preinit_array and .init_array (read from the image, so a
# new constructor is counted). There is no other indirect call in the images; a new one fails the check.
#
# The roots and their stacks, from the image's vector table:
# - entry 1, the reset handler: thread mode on MSP, [__stack_limit, __stack_top).
# - every other handler but FAULT_ROOTS: the board's interrupts and Default_Handler. Their priorities stay at reset
#   (0, equal: the firmware writes no priority register), so none preempts another: one at most on top of the thread,
#   with its exception frame (EXCEPTION_FRAME: 8 words, 26 with the FP context, and 4 B of alignment).
# - FAULT_ROOTS (HardFault, NMI) switch to their own stack, the guard [__stack_guard, __stack_limit), before they
#   push anything (startup.cpp); their depth must fit it. Their exception frame goes on the main stack first.
# Passes when reset + (an interrupt + its frame) + a fault's frame <= __stack_top - __stack_limit.

cmake_minimum_required(VERSION 3.25)  # the policies of the project (IN_LIST, empty list elements kept)
foreach(var ELF NM OBJDUMP OBJCOPY OBJECTS EXCEPTION_FRAME)
  if(NOT DEFINED ${var} OR "${${var}}" STREQUAL "")
    message(FATAL_ERROR "StackDepth.cmake: -D${var}=... is required")
  endif()
endforeach()
# Per-function facts as global properties (any string is a property name; CMake variable names are not that free):
# ci:<f> frame from the .ci, qual:<f> its qualifier, mc:<f> frame from machine code, calls:<f>, indirect:<f> where,
# spset:<f> an instruction that sets sp, depth:<f> / next:<f> / state:<f> the search's results.
function(prop_set name value)
  set_property(GLOBAL PROPERTY "${name}" "${value}")
endfunction()
function(prop_add name value)
  set_property(GLOBAL APPEND PROPERTY "${name}" "${value}")
endfunction()
macro(prop_get var name)
  get_property(${var} GLOBAL PROPERTY "${name}")
  if(NOT DEFINED ${var})
    set(${var} "")  # an unset property leaves the variable undefined, and if() would then read its name
  endif()
endmacro()
# Every reason the proof fails, collected (also from inside the recursive search), reported together at the end.
function(fail text)
  set_property(GLOBAL APPEND_STRING PROPERTY errors "  ${text}\n")
endfunction()

# ---- The image: symbols, stack bounds, vector table, constructor tables ------------------------------------------
execute_process(COMMAND "${NM}" "${ELF}" OUTPUT_VARIABLE nm_out RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${NM} failed on ${ELF}")
endif()
# A function is known by the first name nm gives its address (libgcc's routines have several: __aeabi_fadd is
# __addsf3), so that the .ci's names, objdump's and a branch's target meet; only functions are branch targets that
# count as calls (a branch to an address that happens to carry another symbol, __stack_size, stays in its function).
string(REGEX MATCHALL "[0-9a-f]+ [TtWw] [^\n]+" functions "${nm_out}")
foreach(line IN LISTS functions)
  string(REGEX MATCH "^([0-9a-f]+) . (.+)$" _ "${line}")
  math(EXPR address "0x${CMAKE_MATCH_1}" OUTPUT_FORMAT HEXADECIMAL)
  prop_get(known "at:${address}")
  if(known STREQUAL "")
    prop_set("at:${address}" "${CMAKE_MATCH_2}")
    set(known "${CMAKE_MATCH_2}")
  endif()
  prop_set("canonical:${CMAKE_MATCH_2}" "${known}")
endforeach()
macro(canonical var)
  prop_get(_c "canonical:${${var}}")
  if(NOT _c STREQUAL "")
    set(${var} "${_c}")
  endif()
endmacro()
foreach(symbol __stack_guard __stack_limit __stack_top)
  if(NOT nm_out MATCHES "([0-9a-f]+) [A-Za-z] ${symbol}\n")
    message(FATAL_ERROR "${ELF} has no ${symbol} (linker script hal/cortex_m/ld/cortex-m-sections.ld)")
  endif()
  math(EXPR ${symbol} "0x${CMAKE_MATCH_1}")
endforeach()
math(EXPR stack_size "${__stack_top} - ${__stack_limit}")
math(EXPR guard_size "${__stack_limit} - ${__stack_guard}")

# The function symbols a section's words point at (vector table, constructor tables), in order; none if it is absent.
# The section's bytes come through objcopy as a file read back in hex (objdump -s's ASCII column can hold the
# brackets and semicolons that CMake's lists treat specially).
function(section_targets section out)
  set(bin "${ELF}${section}.bin")
  execute_process(COMMAND "${OBJCOPY}" -O binary --only-section=${section} "${ELF}" "${bin}" RESULT_VARIABLE rc)
  set(targets "")
  if(rc EQUAL 0 AND EXISTS "${bin}")
    file(READ "${bin}" hex HEX)
    file(REMOVE "${bin}")
    string(REGEX MATCHALL "........" words "${hex}")
    foreach(word IN LISTS words)  # little-endian bytes: 41010000 is 0x00000141
      string(REGEX REPLACE "^(..)(..)(..)(..)$" "\\4\\3\\2\\1" word "${word}")
      math(EXPR address "0x${word} & ~1" OUTPUT_FORMAT HEXADECIMAL)  # a Thumb function's address has bit 0 set
      prop_get(name "at:${address}")
      if(name STREQUAL "")
        set(name "-")  # the vector table's SP, a reserved entry: no function (a list cannot start with "")
      endif()
      list(APPEND targets "${name}")
    endforeach()
  endif()
  set(${out} "${targets}" PARENT_SCOPE)
endfunction()
section_targets(.isr_vector vectors)
list(LENGTH vectors count)
if(count LESS 16)
  message(FATAL_ERROR "${ELF}: no vector table in .isr_vector")
endif()
list(GET vectors 1 reset)
list(SUBLIST vectors 2 -1 handlers)
list(REMOVE_ITEM handlers - ${FAULT_ROOTS})
list(REMOVE_DUPLICATES handlers)

# ---- The compiler's call graph (.ci) -----------------------------------------------------------------------------
# A title is the function's assembler name, "<file>:<name>" for one with internal linkage, "*<name>" for one declared
# with an asm label: the image's symbol is what follows. Functions of the same name from two files are merged (the
# larger frame, both sets of calls): an over-estimate, never an under-estimate.
function(symbol_of title out)
  string(REGEX REPLACE "^.*:" "" title "${title}")
  string(REGEX REPLACE "^\\*" "" title "${title}")
  canonical(title)
  set(${out} "${title}" PARENT_SCOPE)
endfunction()
foreach(object IN LISTS OBJECTS)
  string(REGEX REPLACE "\\.[^./]+$" ".ci" ci "${object}")
  if(NOT EXISTS "${ci}")
    fail("no call graph ${ci} for ${object} (compiled without -fcallgraph-info=su?)")
    continue()
  endif()
  file(STRINGS "${ci}" lines REGEX "^(node|edge): ")
  foreach(line IN LISTS lines)
    if(line MATCHES "^node: { title: \"([^\"]+)\" label: \".*\\\\n([0-9]+) bytes \\(([a-z,]+)\\)\"")
      set(frame ${CMAKE_MATCH_2})
      set(qualifier ${CMAKE_MATCH_3})
      symbol_of("${CMAKE_MATCH_1}" f)
      prop_get(old "ci:${f}")
      if(old STREQUAL "" OR frame GREATER old)
        prop_set("ci:${f}" ${frame})
      endif()
      if(NOT qualifier STREQUAL "static" AND NOT qualifier STREQUAL "dynamic,bounded")
        prop_set("qual:${f}" "${qualifier}")  # "dynamic": alloca or a VLA, no bound
      endif()
    elseif(line MATCHES "^edge: { sourcename: \"([^\"]+)\" targetname: \"([^\"]+)\"( label: \"([^\"]*)\")?")
      set(target "${CMAKE_MATCH_2}")
      set(where "${CMAKE_MATCH_4}")
      symbol_of("${CMAKE_MATCH_1}" f)
      if(target STREQUAL "__indirect_call")
        prop_add("indirect:${f}" "${where}")
      else()
        symbol_of("${target}" t)
        prop_add("calls:${f}" "${t}")
      endif()
    endif()
  endforeach()
endforeach()

# ---- The machine code (objdump -d) ---------------------------------------------------------------------------------
set(listing_file "${ELF}.stack-listing")
execute_process(COMMAND "${OBJDUMP}" -d --no-show-raw-insn "${ELF}" OUTPUT_FILE "${listing_file}" RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${OBJDUMP} -d failed on ${ELF}")
endif()
# Function starts and every instruction: the frame's pushes and adjustments, the branches, the writes to sp and pc,
# and the last instruction of each function (whether it falls through into the next symbol).
file(STRINGS "${listing_file}" lines REGEX "^[0-9a-f]+ <.+>:$|:\t[a-z.]+(\t|$)")
file(REMOVE "${listing_file}")
# Registers in a list such as "{r4, r5, lr}" or "{d8-d15}", times their size.
function(list_bytes text unit out)
  set(bytes 0)
  string(REGEX MATCHALL "[a-z]+[0-9]*(-[a-z]+[0-9]+)?" items "${text}")
  foreach(item IN LISTS items)
    if(item MATCHES "^[a-z]+([0-9]+)-[a-z]+([0-9]+)$")
      math(EXPR bytes "${bytes} + (${CMAKE_MATCH_2} - ${CMAKE_MATCH_1} + 1) * ${unit}")
    else()
      math(EXPR bytes "${bytes} + ${unit}")
    endif()
  endforeach()
  set(${out} ${bytes} PARENT_SCOPE)
endfunction()
# The larger frame where two functions share a name (static functions of two files).
function(set_mc f frame)
  prop_get(old "mc:${f}")
  if(old STREQUAL "" OR frame GREATER old)
    prop_set("mc:${f}" ${frame})
  endif()
endfunction()
# Whether an instruction ends a function's straight-line flow (an unconditional branch or return): otherwise the
# code runs on into the next symbol, whose frame then comes on top of this one's, as a call's would. libgcc does
# that: __aeabi_dsub is one `eor` that falls into __adddf3 (found in review: without the edge a double subtraction
# on the M3 counted 8 B where it takes 20).
function(ends_flow op args out)
  set(ends FALSE)
  if(op MATCHES "^(b|b\\.w|b\\.n|bx|bx\\.n|udf|udf\\.w)$" OR
     (op MATCHES "^(pop|pop\\.w|ldm|ldmia|ldmia\\.w|ldm\\.w)$" AND args MATCHES "pc") OR
     (op MATCHES "^(ldr|ldr\\.w|mov)$" AND args MATCHES "^pc, "))
    set(ends TRUE)
  endif()
  set(${out} ${ends} PARENT_SCOPE)
endfunction()
set(f "")
set(flow_ends TRUE)  # before the first symbol: nothing to fall from
foreach(line IN LISTS lines)
  if(line MATCHES "^[0-9a-f]+ <(.+)>:$")
    set(next "${CMAKE_MATCH_1}")
    canonical(next)
    if(NOT f STREQUAL "")
      set_mc("${f}" ${frame})
      if(NOT flow_ends AND NOT next STREQUAL f)
        prop_add("calls:${f}" "${next}")  # falls through into the next symbol
      endif()
    endif()
    set(f "${next}")
    set(frame 0)
    set(flow_ends FALSE)
    continue()
  endif()
  if(NOT line MATCHES ":\t([a-z.]+)\t?(.*)$")
    continue()
  endif()
  set(op "${CMAKE_MATCH_1}")
  set(args "${CMAKE_MATCH_2}")
  # Literal pools (.word) and alignment padding after a function's last instruction do not run: nop, and zeros,
  # which disassemble as `movs r0, r0`.
  if(NOT op MATCHES "^(\\.word|\\.short|\\.byte|nop|nop\\.w)$" AND NOT (op STREQUAL "movs" AND args STREQUAL "r0, r0"))
    ends_flow("${op}" "${args}" flow_ends)
  endif()
  set(added 0)
  if(op MATCHES "^(push|stmdb)" AND (op MATCHES "^push" OR args MATCHES "^sp!"))
    string(REGEX MATCH "{[^}]*}" regs "${args}")
    list_bytes("${regs}" 4 added)
  elseif(op MATCHES "^vpush")
    string(REGEX MATCH "{[^}]*}" regs "${args}")
    if(regs MATCHES "d[0-9]")
      list_bytes("${regs}" 8 added)
    else()
      list_bytes("${regs}" 4 added)
    endif()
  elseif(op MATCHES "^sub" AND args MATCHES "^sp, (sp, )?#([0-9]+)")
    set(added ${CMAKE_MATCH_2})
  elseif(op MATCHES "^str" AND args MATCHES "\\[sp, #-([0-9]+)\\]!")
    set(added ${CMAKE_MATCH_1})
  elseif((op MATCHES "^(sub|add)" AND args MATCHES "^sp, " AND NOT args MATCHES "^sp, (sp, )?#") OR
         (op MATCHES "^(mov|ldr)" AND args MATCHES "^sp, ") OR (op STREQUAL "msr" AND args MATCHES "^[MP]SP"))
    prop_add("spset:${f}" "${op} ${args}")  # sp from a register or memory: no static bound
  elseif(op MATCHES "^b" AND args MATCHES "^[0-9a-f]+ <([^>+]+)(\\+0x[0-9a-f]+)?>")
    set(target "${CMAKE_MATCH_1}")
    prop_get(is_function "canonical:${target}")
    canonical(target)
    if(NOT is_function STREQUAL "" AND NOT target STREQUAL f)
      prop_add("calls:${f}" "${target}")  # bl, or b/b.w to another function: a (tail) call
    endif()
  elseif((op MATCHES "^(blx|bx)" AND NOT args STREQUAL "lr") OR
         (op MATCHES "^(mov|ldr)" AND args MATCHES "^pc, " AND NOT args MATCHES "^pc, \\[sp\\]"))
    prop_add("mc_indirect:${f}" "${op} ${args}")  # through a register (ldr pc, [sp], #4 is a return)
  endif()
  math(EXPR frame "${frame} + ${added}")
endforeach()
if(NOT f STREQUAL "")
  set_mc("${f}" ${frame})
endif()

# The machine-code reader checked against the compiler: on every function GCC compiled, the reader's frame is at
# least GCC's (it is larger where a function pushes on two paths), or its numbers for the libraries cannot be trusted.
foreach(line IN LISTS functions)
  string(REGEX REPLACE "^[0-9a-f]+ . " "" f "${line}")
  canonical(f)
  prop_get(by_gcc "ci:${f}")
  prop_get(by_reader "mc:${f}")
  if(NOT by_gcc STREQUAL "" AND NOT by_reader STREQUAL "" AND by_reader LESS by_gcc)
    fail("${f}: the machine code shows ${by_reader} B of frame where GCC counts ${by_gcc} B (the reader misses a push)")
  endif()
endforeach()

# Indirect targets the caller's sections hold: INDIRECT "caller=.preinit_array+.init_array".
foreach(rule IN LISTS INDIRECT)
  if(NOT rule MATCHES "^([^=]+)=(.+)$")
    message(FATAL_ERROR "INDIRECT '${rule}': expected <caller>=<section>[+<section>...]")
  endif()
  set(caller "${CMAKE_MATCH_1}")
  string(REPLACE "+" ";" sections "${CMAKE_MATCH_2}")
  set(resolved "")
  foreach(section IN LISTS sections)
    section_targets(${section} targets)
    list(APPEND resolved ${targets})
  endforeach()
  if("-" IN_LIST resolved)
    fail("${caller}: an entry of ${CMAKE_MATCH_2} is no function of the image")
  endif()
  prop_get(c "calls:${caller}")
  prop_set("calls:${caller}" "${c};${resolved}")
endforeach()

# ---- The deepest path from each root -----------------------------------------------------------------------------
# Depth-first with memoisation; a function met again while it is on the path is recursion. frame(f) is the .ci's
# where GCC emitted f, else the machine code's.
function(depth_of f path out)
  prop_get(state "state:${f}")
  if(state STREQUAL "done")
    prop_get(d "depth:${f}")
    set(${out} ${d} PARENT_SCOPE)
    return()
  elseif(state STREQUAL "open")
    list(APPEND path "${f}")
    list(REMOVE_ITEM path "")
    string(REPLACE ";" " -> " path "${path}")
    fail("recursion: ${path}")
    set(${out} 0 PARENT_SCOPE)
    return()
  endif()
  prop_set("state:${f}" open)
  prop_get(frame "ci:${f}")
  prop_get(indirect "indirect:${f}")
  if(frame STREQUAL "")
    # Not compiled by us: frame and indirect branches from the machine code. Where GCC wrote the .ci, its indirect
    # calls are the .ci's (an `ldr pc, [rN, rM, lsl #2]` there is a switch's jump table, not a call).
    prop_get(frame "mc:${f}")
    prop_get(indirect "mc_indirect:${f}")
  endif()
  if(frame STREQUAL "")
    fail("${f}: called but neither in a .ci nor in the image: no frame size")
    set(frame 0)
  endif()
  prop_get(qualifier "qual:${f}")
  if(qualifier)
    fail("${f}: frame ${frame} B + an unbounded dynamic part (${qualifier}: alloca or a variable-length array)")
  endif()
  prop_get(spset "spset:${f}")
  if(spset AND NOT f IN_LIST ROOTS)
    string(REPLACE ";" ", " spset "${spset}")
    fail("${f}: sets the stack pointer (${spset}): no static bound")
  endif()
  if(indirect AND NOT f IN_LIST INDIRECT_CALLERS)  # an INDIRECT caller's targets are among its calls
    fail("${f}: indirect call at ${indirect}: its targets are unknown (give them in INDIRECT)")
  endif()
  prop_get(calls "calls:${f}")
  list(REMOVE_DUPLICATES calls)
  list(REMOVE_ITEM calls "")
  set(deepest 0)
  set(next "")
  foreach(callee IN LISTS calls)
    depth_of("${callee}" "${path};${f}" d)
    if(d GREATER deepest OR next STREQUAL "")  # the first callee at least, so that the path shows the leaf
      set(deepest ${d})
      set(next "${callee}")
    endif()
  endforeach()
  math(EXPR total "${frame} + ${deepest}")
  prop_set("depth:${f}" ${total})
  prop_set("frame:${f}" ${frame})
  prop_set("next:${f}" "${next}")
  prop_set("state:${f}" done)
  set(${out} ${total} PARENT_SCOPE)
endfunction()
function(path_of f out)
  set(text "")
  while(NOT f STREQUAL "")
    prop_get(frame "frame:${f}")
    string(APPEND text "\n      ${frame} B  ${f}")
    prop_get(f "next:${f}")
  endwhile()
  set(${out} "${text}" PARENT_SCOPE)
endfunction()

set(INDIRECT_CALLERS "")
foreach(rule IN LISTS INDIRECT)
  string(REGEX REPLACE "=.*$" "" caller "${rule}")
  list(APPEND INDIRECT_CALLERS "${caller}")
endforeach()
set(ROOTS "${reset};${FAULT_ROOTS}")
get_filename_component(image "${ELF}" NAME)
depth_of("${reset}" "" thread)
path_of("${reset}" thread_path)
string(CONCAT report "${image}: worst-case stack (cmake/StackDepth.cmake; frames from GCC's -fcallgraph-info, "
              "machine code where GCC wrote none)\n  thread, from ${reset}: ${thread} B${thread_path}\n")
set(irq 0)
set(irq_name "")
foreach(h IN LISTS handlers)
  depth_of("${h}" "" d)
  string(APPEND report "  interrupt ${h}: ${d} B + its exception frame ${EXCEPTION_FRAME} B\n")
  if(d GREATER_EQUAL irq)
    set(irq ${d})
    set(irq_name "${h}")
  endif()
endforeach()
foreach(h IN LISTS FAULT_ROOTS)
  if(NOT h IN_LIST vectors)
    fail("${h}: named in FAULT_ROOTS but not in the vector table")
    continue()
  endif()
  depth_of("${h}" "" d)
  path_of("${h}" p)
  string(APPEND report "  fault handler ${h}, on its own stack (the guard, ${guard_size} B): ${d} B${p}\n")
  if(d GREATER guard_size)
    fail("${h}: ${d} B on its own stack of ${guard_size} B (__stack_guard to __stack_limit)")
  endif()
endforeach()
math(EXPR worst "${thread} + ${EXCEPTION_FRAME} + ${irq} + ${EXCEPTION_FRAME}")
string(APPEND report "  worst case: thread ${thread} + ${irq_name} ${irq} + 2 exception frames of ${EXCEPTION_FRAME}"
                     " (the interrupt's, a fault's) = ${worst} B of the ${stack_size} B stack (margin ")
math(EXPR margin "${stack_size} - ${worst}")
string(APPEND report "${margin} B)\n")
message("${report}")
if(worst GREATER stack_size)
  fail("worst case ${worst} B exceeds the stack of ${stack_size} B (__stack_top - __stack_limit)")
endif()
prop_get(errors errors)
if(NOT errors STREQUAL "")
  message(FATAL_ERROR "${image}: the stack depth is not proved:\n${errors}")
endif()
