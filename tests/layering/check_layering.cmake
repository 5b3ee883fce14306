# Checks that every `#include "lashid/<layer>/..."` in the source tree points along an allowed arrow of
# docs/architecture.md: a folder may include its own layer and the layers listed for it below, nothing else.
# The CMake link graph already stops most wrong includes at compile time (a target sees only the headers of the
# layers it links); this check also catches the arrows a link would make legal, such as a new link from the HAL
# to the simulator, and names the file and line.
#
# Usage: cmake -DROOT=<source dir> [-DPARTIAL=ON] -P check_layering.cmake
# PARTIAL=ON checks only the folders that exist (the test's fixture tree), not that the table covers host_sim/.
cmake_minimum_required(VERSION 3.25)
if(NOT ROOT)
  message(FATAL_ERROR "check_layering: pass -DROOT=<source dir>")
endif()

# folder (relative to ROOT) -> layers it may include besides its own. Keep in step with docs/architecture.md.
set(allowed_estimator "")
set(allowed_hal "")
set(allowed_firmware "estimator;hal")
set(allowed_host_sim/io "estimator")
set(allowed_host_sim/plant "")
set(allowed_host_sim/stats "")
# sim -> firmware: a simulated run applies the device's own validation excitation (fw::ValidationExcitation) to a
# fw::RunDesign, so simulated and firmware recordings of one config compare; firmware is header-only and host-free.
set(allowed_host_sim/sim "io;plant;estimator;firmware")
set(allowed_host_sim/identify "io;estimator")
set(allowed_host_sim/paper "sim;identify;io;plant;estimator;firmware")
set(allowed_host_sim/analysis "io;plant;stats;estimator")
set(allowed_host_sim/diagnose "analysis;identify;stats;io;plant;estimator")
set(allowed_host_sim/operator_fit "io;plant;stats")
set(allowed_host_sim/hil "firmware;hal;sim;stats;io;plant;estimator")
set(allowed_host_sim/report "io;identify;analysis;diagnose;operator_fit;paper;hil;stats;plant;estimator;firmware;hal;sim")
set(allowed_host_sim/app "io;plant;stats;sim;identify;paper;analysis;diagnose;operator_fit;hil;report;estimator;firmware;hal")
set(folders estimator hal firmware host_sim/io host_sim/plant host_sim/stats host_sim/sim host_sim/identify host_sim/paper
            host_sim/analysis host_sim/diagnose host_sim/operator_fit host_sim/hil host_sim/report host_sim/app)

set(violations 0)
set(checked 0)
foreach(folder IN LISTS folders)
  if(NOT IS_DIRECTORY "${ROOT}/${folder}")
    if(PARTIAL)
      continue()
    endif()
    message(SEND_ERROR "check_layering: folder '${folder}' is in the table but not in the tree")
    math(EXPR violations "${violations} + 1")
    continue()
  endif()
  # The layer's own name: the last path component (host_sim/io -> io).
  get_filename_component(own "${folder}" NAME)
  set(allowed ${own} ${allowed_${folder}})
  file(GLOB_RECURSE sources "${ROOT}/${folder}/*.hpp" "${ROOT}/${folder}/*.cpp" "${ROOT}/${folder}/*.h")
  foreach(source IN LISTS sources)
    math(EXPR checked "${checked} + 1")
    file(STRINGS "${source}" lines REGEX "^[ \t]*#[ \t]*include[ \t]*[\"<]lashid/")
    foreach(line IN LISTS lines)
      string(REGEX REPLACE "^[ \t]*#[ \t]*include[ \t]*[\"<]lashid/([A-Za-z0-9_]+)/.*$" "\\1" layer "${line}")
      if(NOT layer IN_LIST allowed)
        file(RELATIVE_PATH relative "${ROOT}" "${source}")
        message(SEND_ERROR "${relative}: '${line}' includes layer '${layer}', which '${folder}' may not use "
                           "(allowed: ${allowed}; see docs/architecture.md)")
        math(EXPR violations "${violations} + 1")
      endif()
    endforeach()
  endforeach()
endforeach()

# host_sim must hold exactly the folders of the table (a new layer needs its arrows first).
set(host_folders)
if(NOT PARTIAL)
  file(GLOB host_folders LIST_DIRECTORIES true RELATIVE "${ROOT}" "${ROOT}/host_sim/*")
endif()
foreach(folder IN LISTS host_folders)
  if(IS_DIRECTORY "${ROOT}/${folder}" AND NOT folder IN_LIST folders)
    message(SEND_ERROR "check_layering: '${folder}' has no entry in the layer table of check_layering.cmake")
    math(EXPR violations "${violations} + 1")
  endif()
endforeach()

if(violations GREATER 0)
  message(FATAL_ERROR "check_layering: ${violations} include(s) against the layering in ${checked} files")
endif()
message(STATUS "check_layering: ${checked} files, every include points along an allowed arrow")
