# Install tree and Debian package (included by the top-level CMakeLists.txt after the targets).
#   cmake --install build --prefix PREFIX   installs
#     bin/cagekit                                        the CLI (RUNPATH $ORIGIN/../<libdir>)
#     <libdir>/libcagekit.so.<version>, .so.2, .so        the C ABI (SONAME libcagekit.so.2)
#     include/cagekit/cagekit.h, cagekit_gl.h            the public C99 headers (GL binding opt-in)
#     include/cagekit/cagekit.hpp, cagekit_gl.hpp        the header-only C++17 layer over them
#     <libdir>/cmake/CageKit/CageKit{Config,ConfigVersion,Targets,Targets-<config>}.cmake
#                                                        find_package(CageKit) -> CageKit::cagekit
#     <libdir>/pkgconfig/cagekit.pc                      pkg-config cagekit
#     share/doc/cagekit/copyright                        the license statement (GPL-3.0-or-later)
#   cpack -G DEB (in the build folder)                   cagekit_<version>_<arch>.deb of the same tree
# The install rules of the targets are next to them (sdk/capi, samples/cli); tests/packaging checks
# the installed tree, a consumer built against it alone, and the .deb.
include(CMakePackageConfigHelpers)

set(CAGEKIT_CMAKE_INSTALL_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/CageKit)

# CageKit::cagekit. libcagekit links the SDK's static libraries and their dependencies (CGAL,
# OpenSubdiv, Draco, ...) PRIVATE: as a shared library, none of them is in the exported interface.
install(EXPORT CageKitTargets
  NAMESPACE CageKit::
  DESTINATION ${CAGEKIT_CMAKE_INSTALL_DIR})
configure_package_config_file(
  ${PROJECT_SOURCE_DIR}/packaging/cmake/CageKitConfig.cmake.in
  ${PROJECT_BINARY_DIR}/packaging/CageKitConfig.cmake
  INSTALL_DESTINATION ${CAGEKIT_CMAKE_INSTALL_DIR}
  PATH_VARS CMAKE_INSTALL_INCLUDEDIR)
write_basic_package_version_file(
  ${PROJECT_BINARY_DIR}/packaging/CageKitConfigVersion.cmake
  VERSION ${PROJECT_VERSION}
  COMPATIBILITY SameMajorVersion)
install(FILES
  ${PROJECT_BINARY_DIR}/packaging/CageKitConfig.cmake
  ${PROJECT_BINARY_DIR}/packaging/CageKitConfigVersion.cmake
  DESTINATION ${CAGEKIT_CMAKE_INSTALL_DIR})

# cagekit.pc: relative to ${pcfiledir} so that `--prefix` at install time (and moving the tree)
# keeps it right; absolute when the install dirs were given as absolute paths.
if(IS_ABSOLUTE "${CMAKE_INSTALL_LIBDIR}" OR IS_ABSOLUTE "${CMAKE_INSTALL_INCLUDEDIR}")
  set(CAGEKIT_PC_PREFIX "${CMAKE_INSTALL_PREFIX}")
  set(CAGEKIT_PC_LIBDIR "${CMAKE_INSTALL_FULL_LIBDIR}")
  set(CAGEKIT_PC_INCLUDEDIR "${CMAKE_INSTALL_FULL_INCLUDEDIR}")
else()
  file(RELATIVE_PATH pc_up /prefix/${CMAKE_INSTALL_LIBDIR}/pkgconfig /prefix)
  string(REGEX REPLACE "/$" "" pc_up "${pc_up}")
  set(CAGEKIT_PC_PREFIX "\${pcfiledir}/${pc_up}")
  set(CAGEKIT_PC_LIBDIR "\${prefix}/${CMAKE_INSTALL_LIBDIR}")
  set(CAGEKIT_PC_INCLUDEDIR "\${prefix}/${CMAKE_INSTALL_INCLUDEDIR}")
endif()
configure_file(${PROJECT_SOURCE_DIR}/packaging/cmake/cagekit.pc.in ${PROJECT_BINARY_DIR}/packaging/cagekit.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/packaging/cagekit.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)

# The license statement (Debian copyright format; the GPL-3 text itself is in every Debian
# system's /usr/share/common-licenses/GPL-3).
install(FILES ${PROJECT_SOURCE_DIR}/packaging/copyright DESTINATION ${CMAKE_INSTALL_DATAROOTDIR}/doc/cagekit)

# Debian package: one package with the library, header, CMake package, pkg-config file and CLI.
if(CMAKE_SOURCE_DIR STREQUAL PROJECT_SOURCE_DIR)
  set(CPACK_GENERATOR DEB)
  set(CPACK_PACKAGE_NAME cagekit)
  set(CPACK_PACKAGE_VENDOR "CageKit developers")
  set(CPACK_PACKAGE_CONTACT "CageKit developers")
  set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
  set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
      "structure-preserving Catmull-Clark models from dense triangle meshes")
  set(CPACK_PACKAGE_DESCRIPTION
      "CageKit turns dense triangle meshes (3D scans, tessellated CAD parts) into coarse quad-dominant Catmull-Clark control cages with crease edges whose limit surface is fitted to the scan, and deforms the scan through them. This package holds libcagekit (C ABI), its C99 header, the CMake package (find_package(CageKit)), the pkg-config file and the cagekit command-line tool. License: GPL-3.0-or-later.")
  set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
  set(CPACK_STRIP_FILES ON)
  set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
  set(CPACK_DEBIAN_PACKAGE_MAINTAINER "CageKit developers")
  set(CPACK_DEBIAN_PACKAGE_SECTION science)
  # Depends: from dpkg-shlibdeps (dpkg-dev) over the package's ELF files; shlibs for libcagekit.so.2.
  set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
  set(CPACK_DEBIAN_PACKAGE_GENERATE_SHLIBS ON)
  set(CPACK_DEBIAN_PACKAGE_GENERATE_SHLIBS_POLICY ">=")
  set(CPACK_RPM_PACKAGE_LICENSE GPL-3.0-or-later)
  set(CPACK_SOURCE_GENERATOR TGZ)
  set(CPACK_SOURCE_IGNORE_FILES "/\\\\.git/" "/build[^/]*/" "/out[^/]*/" "__pycache__")
  include(CPack)
endif()
