# SPDX-License-Identifier: GPL-3.0-or-later
# Builds the Blender add-on zip (CMake target blender_addon_zip; the ctest fixture of
# blender.addon_zip runs it too):
#   cmake -DSOURCE_DIR=<repo>/bindings -DLIBRARY=<libcagekit.so> -DSONAME=<libcagekit.so.N> -DSTAGE=<dir> -DZIP=<out.zip>
#         [-DUSER_SCRIPTS=<scratch dir to empty>] -P make_addon_zip.cmake
# Layout (one top-level folder, valid as a Blender 3.x add-on and as a 4.2+ extension):
#   cagekit_blender/__init__.py, operators.py, ..., blender_manifest.toml
#   cagekit_blender/cagekit/  the Python package, with libcagekit.so.N (its SONAME) next to its files
foreach(var SOURCE_DIR LIBRARY SONAME STAGE ZIP)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "make_addon_zip.cmake: -D${var}= is missing")
  endif()
endforeach()
if(NOT EXISTS "${LIBRARY}")
  message(FATAL_ERROR "make_addon_zip.cmake: library ${LIBRARY} not built")
endif()
file(REMOVE_RECURSE "${STAGE}")
file(MAKE_DIRECTORY "${STAGE}")
file(COPY "${SOURCE_DIR}/blender/cagekit_blender" DESTINATION "${STAGE}"
     PATTERN "__pycache__" EXCLUDE PATTERN "*.pyc" EXCLUDE)
file(COPY "${SOURCE_DIR}/python/cagekit" DESTINATION "${STAGE}/cagekit_blender"
     PATTERN "__pycache__" EXCLUDE PATTERN "*.pyc" EXCLUDE)
# the real file (not the .so symlink chain) under the name the package looks for first
file(REAL_PATH "${LIBRARY}" real)
file(COPY_FILE "${real}" "${STAGE}/cagekit_blender/cagekit/${SONAME}")
file(REMOVE "${ZIP}")
execute_process(COMMAND "${CMAKE_COMMAND}" -E tar cf "${ZIP}" --format=zip cagekit_blender
                WORKING_DIRECTORY "${STAGE}" RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "make_addon_zip.cmake: zip failed (${rc})")
endif()
message(STATUS "Blender add-on: ${ZIP}")
if(DEFINED USER_SCRIPTS)  # the test's scratch BLENDER_USER_SCRIPTS, emptied
  file(REMOVE_RECURSE "${USER_SCRIPTS}")
  file(MAKE_DIRECTORY "${USER_SCRIPTS}")
endif()
