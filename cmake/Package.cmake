# The Debian package (docs/package.md): CPack's DEB generator over the install rules of cmake/Install.cmake, so the
# .deb holds exactly what `cmake --install` puts into a prefix, under /usr:
#   cpack -G DEB --config <tree>/CPackConfig.cmake     (or `cmake --build <tree> --target package`,
#   cpack --preset host-release, cmake --workflow --preset deb)  ->  lashid_<version>_<arch>.deb
# Included by the top-level CMakeLists.txt in host builds that have the `lashid` tool (a cross build installs headers
# only, and dpkg's architecture would be the build machine's, not the target's). Checked by the CTest
# package_deb_builds_and_a_consumer_builds_against_its_extracted_tree (tests/package/deb_check.sh).
#
# Depends: computed by dpkg-shlibdeps from the tool's ELF (CPACK_DEBIAN_PACKAGE_SHLIBDEPS; needs dpkg-dev and file,
# .ci/install-deps), plus Eigen, which the installed package config asks for with find_dependency(Eigen3 3.4) and
# which no ELF records (header-only).

set(LASHID_PACKAGE_CONTACT "lashid maintainers <maintainers@users.noreply.h-seed-fb4af9d4.example>" CACHE STRING
    "Maintainer of the .deb, 'Name <address>' (default: the author of the repository's commits)")

set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME lashid)
set(CPACK_PACKAGE_VERSION "${PROJECT_VERSION}")
set(CPACK_PACKAGE_CONTACT "${LASHID_PACKAGE_CONTACT}")
# The control file's first Description line (CPack puts the paragraph below under it).
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "${PROJECT_DESCRIPTION}")
# Lines under 80 characters, as dpkg shows them; CPack indents them by one space.
string(JOIN "\n" CPACK_DEBIAN_PACKAGE_DESCRIPTION
  "Identification of actuators whose input passes through a backlash or switch"
  "nonlinearity and then through linear dynamics, by the descendent and ascendent"
  "schemes (DIS, AIS) of Giri, Rochdi, Brouri and Chaoui (Automatica): the linear"
  "part and the border values at chosen levels are estimated by least squares,"
  "with no shape assumed for the borders."
  ""
  "This package holds the lashid command-line tool (simulate, identify, design,"
  "diagnose, operator-fit, reproduce the paper, and hil, which runs a Cortex-M"
  "firmware image in qemu-system-arm; no image is included), the header-only,"
  "heap-free estimator, HAL and firmware headers with their CMake package"
  "(find_package(lashid CONFIG): lashid::estimator, lashid::hal,"
  "lashid::hal_host, lashid::firmware), and the documentation.")
# No homepage: the project publishes none.
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_PRIORITY optional)
# lashid_<version>_<arch>.deb (no Debian revision is set, so none is in the name).
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_DEPENDS "libeigen3-dev (>= 3.4)")
# What the tool starts, found on PATH at run time: `lashid hil` qemu-system-arm, `operator-fit --plot` gnuplot.
set(CPACK_DEBIAN_PACKAGE_SUGGESTS "qemu-system-arm, gnuplot-nox | gnuplot")
set(CPACK_DEBIAN_COMPRESSION_TYPE xz)
# The tool without its symbol table, as Debian ships binaries (a Release build has no debug information to lose).
set(CPACK_STRIP_FILES ON)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
# `package_source` (which include(CPack) also defines) must not pack the build trees.
set(CPACK_SOURCE_IGNORE_FILES "/\\.git/" "/build/")
# The values above reach CPackConfig.cmake as written (CPack escapes them).
set(CPACK_VERBATIM_VARIABLES ON)

include(CPack)
