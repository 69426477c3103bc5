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
