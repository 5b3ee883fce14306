# Cortex-M firmware images for the board of the cross build (LASHID_BOARD: mps2 with presets cm4f-release,
# cm7-release, cm3-release; stm32f4 with stm32f405-release). See docs/firmware-platform.md and docs/porting.md.
#
#   lashid_add_firmware(<target> SOURCES <file>... [LIBS <library>...] [TIMEOUT <seconds>] [NO_RUN_TEST]
#                       [NO_STACK_CHECK] [STACK_SIZE <bytes>] [MAX_FLASH <bytes>] [MAX_RAM <bytes>])
#
# builds <target>.elf against the board library (lashid::hal_${LASHID_BOARD}) with the linker script that library names
# in its LASHID_LINKER_SCRIPT property (and a stack of STACK_SIZE bytes instead of the script's 16 KiB), prints a flash/RAM report after each link, and
# registers three tests, four with a budget:
#   <target>_runs_in_qemu   runs the ELF in qemu-system-arm (CMAKE_CROSSCOMPILING_EMULATOR); passes on exit code 0,
#                           fails on any other code or after TIMEOUT seconds (default 60: a hang fails); not with
#                           NO_RUN_TEST (images that need a peer on their UARTs, tested through `lashid hil`)
#   <target>_is_heap_free   fails if the linked ELF defines or references any allocator symbol (malloc, free, calloc,
#                           realloc, their _r variants, _sbrk, _sbrk_r, operator new/delete): the proof is the link
#   <target>_fits_its_budget  fails if flash exceeds MAX_FLASH or RAM (static + the reserved stack) exceeds MAX_RAM
#   <target>_has_no_semihosting_trap  with LASHID_SEMIHOSTING OFF (a board without a debugger), instead of the run in
#                           QEMU: fails if the image holds a `bkpt` (the semihosting trap, which faults there)
#   <target>_stack_fits     the worst-case stack depth, proved from the compiler's call graph (cmake/StackDepth.cmake):
#                           fails on recursion, an unbounded frame, an unresolved indirect call, or a worst case
#                           beyond the reserved stack; not with NO_STACK_CHECK (an image that overflows on purpose)
#
# This file is also the script those two steps run (cmake -P with LASHID_FIRMWARE_ACTION = size | heap-check).

if(CMAKE_SCRIPT_MODE_FILE AND DEFINED LASHID_FIRMWARE_ACTION)
  if(LASHID_FIRMWARE_ACTION STREQUAL "size")
    # Flash = everything loaded from the image (text, read-only data, vectors, init arrays, .data's initial values);
    # RAM = .data + .bss + the reserved stack. arm-none-eabi-size's Berkeley columns: text | data | bss (bss includes
    # the NOLOAD .stack reservation).
    execute_process(COMMAND "${SIZE}" -B -d "${ELF}" OUTPUT_VARIABLE berkeley RESULT_VARIABLE rc)
    if(NOT rc EQUAL 0)
      message(FATAL_ERROR "${SIZE} failed on ${ELF}")
    endif()
    execute_process(COMMAND "${SIZE}" -A -d "${ELF}" OUTPUT_VARIABLE sysv)
    string(REGEX MATCH "\n[ \t]*([0-9]+)[ \t]+([0-9]+)[ \t]+([0-9]+)[ \t]+[0-9]+" row "${berkeley}")
    if(NOT row)
      message(FATAL_ERROR "cannot read the sizes of ${ELF}:\n${berkeley}")
    endif()
    set(text ${CMAKE_MATCH_1})
    set(data ${CMAKE_MATCH_2})
    set(bss ${CMAKE_MATCH_3})
    set(stack 0)
    if(sysv MATCHES "\n\\.stack[ \t]+([0-9]+)")
      set(stack ${CMAKE_MATCH_1})
    endif()
    set(psram 0)
    if(sysv MATCHES "\n\\.psram[ \t]+([0-9]+)")
      set(psram ${CMAKE_MATCH_1})
    endif()
    math(EXPR flash "${text} + ${data}")
    math(EXPR ram "${data} + ${bss} - ${psram}")
    math(EXPR static_ram "${ram} - ${stack}")
    get_filename_component(name "${ELF}" NAME)
    message("${name}: text ${text}, data ${data}, bss ${bss} (arm-none-eabi-size) -> flash ${flash} B, "
            "RAM ${ram} B = stack ${stack} + static ${static_ram}"
            "; stack high-water: printed by the image at exit")
    if(DEFINED MAX_FLASH AND flash GREATER MAX_FLASH)
      message(FATAL_ERROR "${name}: flash ${flash} B exceeds its budget of ${MAX_FLASH} B")
    endif()
    if(DEFINED MAX_RAM AND ram GREATER MAX_RAM)
      message(FATAL_ERROR "${name}: RAM ${ram} B (static ${static_ram} + stack ${stack}) exceeds its budget of "
                          "${MAX_RAM} B")
    endif()
    return()
  elseif(LASHID_FIRMWARE_ACTION STREQUAL "heap-check")
    execute_process(COMMAND "${NM}" "${ELF}" OUTPUT_VARIABLE symbols RESULT_VARIABLE rc)
    if(NOT rc EQUAL 0)
      message(FATAL_ERROR "${NM} failed on ${ELF}")
    endif()
    # Mangled operator new/delete: _Znwj _Znaj (+ nothrow/align_val_t overloads), _ZdlPv _ZdaPv (+ sized etc.).
    set(allocators "malloc|free|calloc|realloc|reallocf|memalign|aligned_alloc|posix_memalign|valloc|pvalloc"
                   "|_malloc_r|_free_r|_calloc_r|_realloc_r|_memalign_r|_sbrk|_sbrk_r|_Zn[wa][jm][A-Za-z0-9_]*"
                   "|_Zd[la]Pv[A-Za-z0-9_]*")
    string(JOIN "" allocators ${allocators})
    string(REGEX MATCHALL "[^\n]* (${allocators})\n" offending "${symbols}\n")
    # Placement new/delete (operator new(size_t, void*) etc.) allocate nothing; unoptimised builds keep them.
    list(FILTER offending EXCLUDE REGEX " (_ZnwjPv|_ZnajPv|_ZdlPvS_|_ZdaPvS_)\n$")
    list(LENGTH offending count)
    if(count GREATER 0)
      string(REPLACE ";" "" offending "${offending}")
      message(FATAL_ERROR "${ELF} links heap allocator symbols (nm):\n${offending}")
    endif()
    string(REGEX MATCHALL "\n" lines "${symbols}")
    list(LENGTH lines total)
    message(STATUS "${ELF}: none of ${total} symbols is an allocator (malloc/free/calloc/realloc/_sbrk/new/delete)")
    return()
  else()
    message(FATAL_ERROR "Firmware.cmake: unknown LASHID_FIRMWARE_ACTION '${LASHID_FIRMWARE_ACTION}'")
  endif()
endif()

include_guard(GLOBAL)

set(_lashid_firmware_script "${CMAKE_CURRENT_LIST_FILE}")
set(_lashid_no_trap_script "${CMAKE_CURRENT_LIST_DIR}/NoSemihostingTrap.cmake")
set(_lashid_stack_depth_script "${CMAKE_CURRENT_LIST_DIR}/StackDepth.cmake")

# The targets with object files linked into <target> (itself and the static and object libraries it links, through
# their interface links too): their objects' call graphs (<object>.ci) are the stack check's input.
function(_lashid_object_targets target out)
  set(found "")
  set(pending ${target})
  while(pending)
    list(POP_FRONT pending t)
    string(REGEX REPLACE "^\\$<LINK_ONLY:(.*)>$" "\\1" t "${t}")
    if(NOT TARGET "${t}")
      continue()  # a flag, a file or a system library: no objects of ours
    endif()
    get_target_property(aliased ${t} ALIASED_TARGET)
    if(aliased)
      set(t ${aliased})
    endif()
    if(t IN_LIST found)
      continue()
    endif()
    list(APPEND found ${t})
    get_target_property(type ${t} TYPE)
    set(links "")
    if(NOT type STREQUAL "INTERFACE_LIBRARY")
      get_target_property(links ${t} LINK_LIBRARIES)
    endif()
    get_target_property(interface_links ${t} INTERFACE_LINK_LIBRARIES)
    foreach(list_of links interface_links)
      if(${list_of})
        list(APPEND pending ${${list_of}})
      endif()
    endforeach()
  endwhile()
  set(objects "")
  foreach(t IN LISTS found)
    get_target_property(type ${t} TYPE)
    if(type MATCHES "^(EXECUTABLE|STATIC_LIBRARY|OBJECT_LIBRARY)$")
      list(APPEND objects "$<TARGET_OBJECTS:${t}>")
    endif()
  endforeach()
  set(${out} "${objects}" PARENT_SCOPE)
endfunction()

function(lashid_add_firmware target)
  cmake_parse_arguments(PARSE_ARGV 1 arg "NO_RUN_TEST;NO_STACK_CHECK" "TIMEOUT;STACK_SIZE;MAX_FLASH;MAX_RAM"
                        "SOURCES;LIBS")
  if(NOT CMAKE_CROSSCOMPILING)
    message(FATAL_ERROR "lashid_add_firmware(${target}): firmware images are built by the cross presets only")
  endif()
  if(NOT arg_SOURCES)
    message(FATAL_ERROR "lashid_add_firmware(${target}): no SOURCES")
  endif()
  if(arg_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "lashid_add_firmware(${target}): unexpected arguments ${arg_UNPARSED_ARGUMENTS}")
  endif()
  if(NOT arg_TIMEOUT)
    set(arg_TIMEOUT 60)
  endif()
  find_program(LASHID_ARM_SIZE NAMES arm-none-eabi-size REQUIRED)

  add_executable(${target} ${arg_SOURCES})
  # The board library provides the linker script (its MEMORY map + hal/cortex_m's sections) and the files it includes.
  set(board lashid::hal_${LASHID_BOARD})
  if(NOT TARGET ${board})
    message(FATAL_ERROR "lashid_add_firmware(${target}): no board library ${board} (LASHID_BOARD '${LASHID_BOARD}')")
  endif()
  target_link_libraries(${target} PRIVATE ${arg_LIBS} ${board} lashid::warnings)
  # The map file next to the image (a -Map=. in the toolchain's flags put every map in the build root, named after
  # the image but away from it).
  target_link_options(${target} PRIVATE "LINKER:-Map=$<TARGET_FILE:${target}>.map")
  get_target_property(script ${board} LASHID_LINKER_SCRIPT)
  get_target_property(script_depends ${board} LASHID_LINKER_SCRIPT_DEPENDS)
  if(NOT script)
    message(FATAL_ERROR "lashid_add_firmware(${target}): ${board} names no LASHID_LINKER_SCRIPT")
  endif()
  target_link_options(${target} PRIVATE "-T${script}")
  if(arg_STACK_SIZE)
    target_link_options(${target} PRIVATE "-Wl,--defsym=__stack_size=${arg_STACK_SIZE}")
  endif()
  set_property(TARGET ${target} APPEND PROPERTY LINK_DEPENDS ${script_depends})
  add_custom_command(TARGET ${target} POST_BUILD
    COMMAND ${CMAKE_COMMAND} -DLASHID_FIRMWARE_ACTION=size -DSIZE=${LASHID_ARM_SIZE} -DELF=$<TARGET_FILE:${target}>
            -DTARGET=${target} -P ${_lashid_firmware_script}
    VERBATIM)

  # The target's CROSSCOMPILING_EMULATOR (qemu-system-arm ... -kernel) runs it; CTest appends the ELF's path.
  if(NOT arg_NO_RUN_TEST AND LASHID_SEMIHOSTING)
    add_test(NAME ${target}_runs_in_qemu COMMAND ${target})
    set_tests_properties(${target}_runs_in_qemu PROPERTIES TIMEOUT ${arg_TIMEOUT} LABELS "firmware;qemu")
  endif()
  if(NOT LASHID_SEMIHOSTING)
    # Built for a board without a debugger: no semihosting trap anywhere in the image.
    add_test(NAME ${target}_has_no_semihosting_trap
             COMMAND ${CMAKE_COMMAND} -DOBJDUMP=${CMAKE_OBJDUMP} -DFILES=$<TARGET_FILE:${target}>
                     -P ${_lashid_no_trap_script})
    set_tests_properties(${target}_has_no_semihosting_trap PROPERTIES TIMEOUT 60 LABELS "firmware")
  endif()
  add_test(NAME ${target}_is_heap_free
           COMMAND ${CMAKE_COMMAND} -DLASHID_FIRMWARE_ACTION=heap-check -DNM=${CMAKE_NM}
                   -DELF=$<TARGET_FILE:${target}> -P ${_lashid_firmware_script})
  set_tests_properties(${target}_is_heap_free PROPERTIES TIMEOUT 60 LABELS "firmware")
  if(NOT arg_NO_STACK_CHECK)
    # An exception frame: 8 words, 26 with the FP context (a core whose code uses FP registers), and 4 B of alignment.
    set(exception_frame 36)
    if(LASHID_CPU_FLAGS MATCHES "-mfloat-abi=(hard|softfp)")
      set(exception_frame 108)
    endif()
    _lashid_object_targets(${target} objects)
    add_test(NAME ${target}_stack_fits
             COMMAND ${CMAKE_COMMAND} -DELF=$<TARGET_FILE:${target}> -DNM=${CMAKE_NM} -DOBJDUMP=${CMAKE_OBJDUMP}
                     -DOBJCOPY=${CMAKE_OBJCOPY}
                     "-DOBJECTS=${objects}" -DEXCEPTION_FRAME=${exception_frame}
                     # The startup (hal/cortex_m/src/startup.cpp) calls the static constructors through these tables.
                     "-DINDIRECT=lashid_cortex_m_start=.preinit_array+.init_array"
                     # Their handlers switch to the fault stack before they push anything (startup.cpp).
                     "-DFAULT_ROOTS=HardFault_Handler;NMI_Handler"
                     -P ${_lashid_stack_depth_script})
    set_tests_properties(${target}_stack_fits PROPERTIES TIMEOUT 120 LABELS "firmware")
  endif()
  if(arg_MAX_FLASH OR arg_MAX_RAM)
    set(budget)
    if(arg_MAX_FLASH)
      list(APPEND budget -DMAX_FLASH=${arg_MAX_FLASH})
    endif()
    if(arg_MAX_RAM)
      list(APPEND budget -DMAX_RAM=${arg_MAX_RAM})
    endif()
    add_test(NAME ${target}_fits_its_budget
             COMMAND ${CMAKE_COMMAND} -DLASHID_FIRMWARE_ACTION=size -DSIZE=${LASHID_ARM_SIZE} ${budget}
                     -DELF=$<TARGET_FILE:${target}> -P ${_lashid_firmware_script})
    set_tests_properties(${target}_fits_its_budget PROPERTIES TIMEOUT 60 LABELS "firmware")
  endif()
endfunction()
