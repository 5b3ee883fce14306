# The installable package (issue 11): `cmake --install <build> --prefix P` puts
#   P/include/lashid/...                         the headers of the estimator, the HAL, the host board, the firmware
#   P/lib/cmake/lashid/lashid{Config,ConfigVersion,Targets}.cmake
#   P/bin/lashid                                  the command-line tool (host builds)
#   P/share/doc/lashid/                           README, docs/, `copyright`, and tests/data/friction_damper/{README.md,
#                                                 LICENSE} of the data that docs/friction-damper.png is drawn from
# so that another project can write find_package(lashid 0.1 CONFIG REQUIRED) and link lashid::estimator (header-only,
# heap-free, Eigen as its one dependency), lashid::hal, lashid::hal_host or lashid::firmware, on the host or in a
# Cortex-M build with the same toolchain file. The host layers (lashid::io ... lashid::report) are the tool's
# internals and are not installed. docs/package.md.
include(CMakePackageConfigHelpers)

set(LASHID_INSTALL_CMAKEDIR "${CMAKE_INSTALL_LIBDIR}/cmake/lashid" CACHE STRING
    "Where the package's CMake files are installed, relative to the prefix")

# Exported as lashid::estimator etc. (the alias names used inside the project).
foreach(name IN ITEMS estimator hal hal_host firmware)
  set_target_properties(lashid_${name} PROPERTIES EXPORT_NAME ${name})
endforeach()
install(TARGETS lashid_estimator lashid_hal lashid_hal_host lashid_firmware EXPORT lashidTargets)
install(DIRECTORY
          "${PROJECT_SOURCE_DIR}/estimator/include/"
          "${PROJECT_SOURCE_DIR}/hal/include/"
          "${PROJECT_SOURCE_DIR}/hal/host/include/"
          "${PROJECT_SOURCE_DIR}/firmware/include/"
        DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}"
        FILES_MATCHING PATTERN "*.hpp")
install(EXPORT lashidTargets NAMESPACE lashid:: DESTINATION "${LASHID_INSTALL_CMAKEDIR}")

configure_package_config_file("${PROJECT_SOURCE_DIR}/cmake/lashidConfig.cmake.in"
                              "${PROJECT_BINARY_DIR}/lashidConfig.cmake"
                              INSTALL_DESTINATION "${LASHID_INSTALL_CMAKEDIR}")
# 0.x: a new minor version may change the API, so only the same minor version is compatible.
write_basic_package_version_file("${PROJECT_BINARY_DIR}/lashidConfigVersion.cmake"
                                 VERSION "${PROJECT_VERSION}" COMPATIBILITY SameMinorVersion ARCH_INDEPENDENT)
install(FILES "${PROJECT_BINARY_DIR}/lashidConfig.cmake" "${PROJECT_BINARY_DIR}/lashidConfigVersion.cmake"
        DESTINATION "${LASHID_INSTALL_CMAKEDIR}")

if(TARGET lashid)
  install(TARGETS lashid RUNTIME DESTINATION "${CMAKE_INSTALL_BINDIR}")
endif()
# The README and docs/ laid out as in the source tree, so that their links to each other hold (the scripts that
# regenerate the damper figure stay behind: they run from a source tree).
install(FILES "${PROJECT_SOURCE_DIR}/README.md" DESTINATION "${CMAKE_INSTALL_DOCDIR}")
install(DIRECTORY "${PROJECT_SOURCE_DIR}/docs/" DESTINATION "${CMAKE_INSTALL_DOCDIR}/docs"
        FILES_MATCHING PATTERN "*.md" PATTERN "*.png" PATTERN "*.json")
# docs/friction-damper.png and .json are computed from the friction damper data (CC BY-SA 4.0): its README (the
# attribution) and licence go with them, at their source path; the CSVs stay behind. `copyright` says which licence
# covers what (the .deb's /usr/share/doc/lashid/copyright).
install(FILES "${PROJECT_SOURCE_DIR}/tests/data/friction_damper/README.md"
              "${PROJECT_SOURCE_DIR}/tests/data/friction_damper/LICENSE"
        DESTINATION "${CMAKE_INSTALL_DOCDIR}/tests/data/friction_damper")
install(FILES "${PROJECT_SOURCE_DIR}/cmake/copyright" DESTINATION "${CMAKE_INSTALL_DOCDIR}")
