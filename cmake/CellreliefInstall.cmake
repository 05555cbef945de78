# SPDX-License-Identifier: MIT
# Install rules and the package configuration: another project does find_package(cellrelief) and
# links cellrelief::cellrelief (or single modules such as cellrelief::io).
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(CELLRELIEF_CMAKE_DIR "${CMAKE_INSTALL_LIBDIR}/cmake/cellrelief")

install(DIRECTORY include/cellrelief DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}"
        FILES_MATCHING PATTERN "*.h" PATTERN "*.ipp")
install(FILES "${PROJECT_BINARY_DIR}/generated/cellrelief/version.h"
        DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}/cellrelief")
install(TARGETS ${CELLRELIEF_EXPORTED_TARGETS} EXPORT cellreliefTargets
        RUNTIME DESTINATION "${CMAKE_INSTALL_BINDIR}"
        LIBRARY DESTINATION "${CMAKE_INSTALL_LIBDIR}"
        ARCHIVE DESTINATION "${CMAKE_INSTALL_LIBDIR}")
install(EXPORT cellreliefTargets NAMESPACE cellrelief:: DESTINATION "${CELLRELIEF_CMAKE_DIR}")

configure_package_config_file(cmake/cellreliefConfig.cmake.in
  "${PROJECT_BINARY_DIR}/cellreliefConfig.cmake" INSTALL_DESTINATION "${CELLRELIEF_CMAKE_DIR}")
write_basic_package_version_file("${PROJECT_BINARY_DIR}/cellreliefConfigVersion.cmake"
  COMPATIBILITY SameMinorVersion)
install(FILES "${PROJECT_BINARY_DIR}/cellreliefConfig.cmake"
              "${PROJECT_BINARY_DIR}/cellreliefConfigVersion.cmake"
              cmake/Findstb.cmake
        DESTINATION "${CELLRELIEF_CMAKE_DIR}")
