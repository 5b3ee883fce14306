# Cross toolchain: bare-metal Cortex-M with the GNU Arm Embedded toolchain (Debian: gcc-arm-none-eabi,
# libnewlib-arm-none-eabi, libstdc++-arm-none-eabi-newlib).
#
# The core is NOT chosen here: the presets (CMakePresets.json, cm*-release) pass the per-core flags in the cache
# variable LASHID_CPU_FLAGS (e.g. "-mcpu=cortex-m4 -mthumb -mfloat-abi=hard -mfpu=fpv4-sp-d16"), which is appended to
# the compile and link flags below, so one toolchain file serves every core and the multilib (newlib, libstdc++,
# libgcc) matching the flags is picked by the driver.
#
#   cmake -S . -B build/x --toolchain toolchains/arm-none-eabi.cmake \
#         -DLASHID_CPU_FLAGS="-mcpu=cortex-m3 -mthumb -mfloat-abi=soft" -DLASHID_QEMU_MACHINE=mps2-an385
set(CMAKE_SYSTEM_NAME Generic)
set(CMAKE_SYSTEM_PROCESSOR arm)

set(CMAKE_C_COMPILER arm-none-eabi-gcc)
set(CMAKE_CXX_COMPILER arm-none-eabi-g++)
set(CMAKE_ASM_COMPILER arm-none-eabi-gcc)

# There is no OS to run a test executable and no crt0 to link one against: check the compiler with a static library.
set(CMAKE_TRY_COMPILE_TARGET_TYPE STATIC_LIBRARY)

set(CMAKE_EXECUTABLE_SUFFIX .elf)
set(CMAKE_EXECUTABLE_SUFFIX_C .elf)
set(CMAKE_EXECUTABLE_SUFFIX_CXX .elf)
set(CMAKE_EXECUTABLE_SUFFIX_ASM .elf)

# Libraries and headers for the target come only from the toolchain's own tree; programs (nm, size, qemu) from the
# host. Header-only, architecture-independent packages (Eigen) are found by the project with NO_CMAKE_FIND_ROOT_PATH.
set(CMAKE_FIND_ROOT_PATH /usr/lib/arm-none-eabi)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)

set(LASHID_CPU_FLAGS "" CACHE STRING
    "Per-core compiler/linker flags (-mcpu, -mthumb, -mfloat-abi, -mfpu), normally set by a cm*-release preset")
if(LASHID_CPU_FLAGS STREQUAL "")
  message(FATAL_ERROR "toolchains/arm-none-eabi.cmake: set LASHID_CPU_FLAGS (use a preset: cm4f-release, "
                      "cm7-release, cm3-release)")
endif()
# The compiler checks run in separate try_compile projects that read this file again: give them the flags too.
list(APPEND CMAKE_TRY_COMPILE_PLATFORM_VARIABLES LASHID_CPU_FLAGS)

# newlib-nano (--specs=nano.specs) for compiling and linking alike: its headers are configured differently from the
# full newlib's. No other specs: no crt0, no nosys/rdimon syscalls (the board support provides what it allows).
set(_lashid_common "${LASHID_CPU_FLAGS} --specs=nano.specs -ffunction-sections -fdata-sections")
set(CMAKE_C_FLAGS_INIT "${_lashid_common}")
set(CMAKE_CXX_FLAGS_INIT
    "${_lashid_common} -fno-exceptions -fno-rtti -fno-threadsafe-statics -fno-use-cxa-atexit")
set(CMAKE_ASM_FLAGS_INIT "${LASHID_CPU_FLAGS} --specs=nano.specs")
# Release for a microcontroller: -O2, not CMake's -O3 (code size matters more than the last few percent). Set as
# cache defaults: CMake appends its own -O3 to any *_FLAGS_RELEASE_INIT, but leaves an existing cache entry alone.
set(CMAKE_C_FLAGS_RELEASE "-O2 -DNDEBUG" CACHE STRING "Flags used by the C compiler during RELEASE builds")
set(CMAKE_CXX_FLAGS_RELEASE "-O2 -DNDEBUG" CACHE STRING "Flags used by the CXX compiler during RELEASE builds")
# Unused sections are dropped (lashid_add_firmware, cmake/Firmware.cmake, also writes each image's map file next to
# it). CMake's link rule also passes the compile flags, so --specs=nano.specs (which may be given only once) is
# already there; the core flags are repeated for links without the C++ flags.
set(CMAKE_EXE_LINKER_FLAGS_INIT "${LASHID_CPU_FLAGS} -Wl,--gc-sections")
unset(_lashid_common)
