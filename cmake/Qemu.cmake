# The machine-independent flags of every qemu-system-arm command line of the project, defined once. Users:
#   - the cross builds' image tests (CMAKE_CROSSCOMPILING_EMULATOR, top-level CMakeLists.txt);
#   - `lashid hil`, which starts QEMU itself (configured into the generated header lashid/hil/qemu_args.hpp);
#   - .ci/main and tests/hil/attach.sh, through `lashid qemu-command`, which prints a whole command line.
# The machine (-machine), the UART backends (-serial) and the image (-kernel) are per use.
#
# -nographic -monitor none: no display, and no QEMU monitor multiplexed onto stdio.
# -semihosting-config enable=on,target=native: semihosting carries the console and the exit code; without it the
#   image's first `bkpt 0xAB` faults (docs/firmware-platform.md).
set(LASHID_QEMU_COMMON_ARGS -nographic -monitor none -semihosting-config enable=on,target=native)
# -icount shift=0: one guest instruction = 1 ns of virtual time, so SysTick (25 MHz) advances one count per 40
# instructions, deterministically (docs/on-target-cost.md). Used by the image tests and the cost benchmark; `lashid
# hil` only on request (--icount), since QEMU then services the UARTs slowly.
set(LASHID_QEMU_ICOUNT_ARGS -icount shift=0)

# lashid_qemu_args_header(<file>): writes <file>, a C++ header with both lists as std::array<std::string_view, N>
# (lashid::sim::kQemuCommonArgs, lashid::sim::kQemuIcountArgs).
function(lashid_qemu_args_header file)
  foreach(list IN ITEMS COMMON ICOUNT)
    set(items "")
    foreach(arg IN LISTS LASHID_QEMU_${list}_ARGS)
      string(APPEND items "\"${arg}\", ")
    endforeach()
    list(LENGTH LASHID_QEMU_${list}_ARGS LASHID_QEMU_${list}_COUNT)
    string(REGEX REPLACE ", $" "" LASHID_QEMU_${list}_ITEMS "${items}")
  endforeach()
  configure_file(${CMAKE_CURRENT_FUNCTION_LIST_DIR}/qemu_args.hpp.in ${file} @ONLY)
endfunction()
