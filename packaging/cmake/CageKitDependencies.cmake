# Finds CageKit's dependencies (Debian 12 packages, installed by packaging/install-deps.sh).

find_package(Threads REQUIRED)
find_package(Eigen3 3.3 REQUIRED NO_MODULE)

# Debian's OpenSubdiv CMake config names static libraries that the package does not ship,
# so imported targets are made from the shared libraries directly.
find_path(OPENSUBDIV_INCLUDE_DIR opensubdiv/version.h REQUIRED)
find_library(OPENSUBDIV_CPU_LIBRARY osdCPU REQUIRED)
if(NOT TARGET OpenSubdiv::osdCPU)
  add_library(OpenSubdiv::osdCPU SHARED IMPORTED)
  set_target_properties(OpenSubdiv::osdCPU PROPERTIES
    IMPORTED_LOCATION "${OPENSUBDIV_CPU_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${OPENSUBDIV_INCLUDE_DIR}")
endif()

find_package(draco CONFIG REQUIRED)

# OpenMesh: the Debian config has no version file; targets OpenMeshCore / OpenMeshTools.
find_package(OpenMesh CONFIG QUIET)

if(CAGEKIT_BUILD_TESTS)
  find_package(GTest REQUIRED)
endif()

# OpenCASCADE (Debian's libocct-*-dev 7.6, config in /usr/lib/<arch>/cmake/opencascade): only for the
# companion library samples/step_export (STEP export of B-spline surfaces, `cagekit export-surfaces`);
# libcagekit never links it. Optional: default ON when found; OFF, the CLI lacks the command.
# The toolkits are linked as their shared libraries (target cagekit_occt), not through Debian's
# imported targets: those name /usr/lib/<arch>/libtbb.so of libtbb-dev, which the OCCT -dev packages
# do not depend on (the .so files themselves need only the runtime libtbb12).
find_package(OpenCASCADE CONFIG QUIET)
set(CAGEKIT_OCCT_TOOLKITS TKSTEP TKSTEPAttr TKSTEPBase TKSTEP209 TKXSBase TKShHealing TKTopAlgo TKGeomAlgo TKBRep
    TKGeomBase TKG3d TKG2d TKMath TKernel)
set(CAGEKIT_OCCT_USABLE ${OpenCASCADE_FOUND})
if(OpenCASCADE_FOUND)
  foreach(toolkit ${CAGEKIT_OCCT_TOOLKITS})
    find_library(CAGEKIT_OCCT_${toolkit} ${toolkit} HINTS ${OpenCASCADE_LIBRARY_DIR} NO_DEFAULT_PATH)
    if(NOT CAGEKIT_OCCT_${toolkit})
      set(CAGEKIT_OCCT_USABLE OFF)
    endif()
  endforeach()
endif()
option(CAGEKIT_WITH_OCCT "Build samples/step_export (OpenCASCADE STEP export) and `cagekit export-surfaces`"
       ${CAGEKIT_OCCT_USABLE})
if(CAGEKIT_WITH_OCCT)
  if(NOT CAGEKIT_OCCT_USABLE)
    message(FATAL_ERROR "CAGEKIT_WITH_OCCT is ON but OpenCASCADE (${CAGEKIT_OCCT_TOOLKITS}) was not found "
                        "(packaging/install-deps.sh)")
  endif()
  add_library(cagekit_occt INTERFACE)
  target_include_directories(cagekit_occt SYSTEM INTERFACE ${OpenCASCADE_INCLUDE_DIR})
  foreach(toolkit ${CAGEKIT_OCCT_TOOLKITS})
    target_link_libraries(cagekit_occt INTERFACE ${CAGEKIT_OCCT_${toolkit}})
  endforeach()
  message(STATUS "OpenCASCADE ${OpenCASCADE_VERSION}: samples/step_export and `cagekit export-surfaces` built")
else()
  message(STATUS "OpenCASCADE not used: no samples/step_export, no `cagekit export-surfaces`")
endif()
