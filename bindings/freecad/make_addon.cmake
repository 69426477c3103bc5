# SPDX-License-Identifier: GPL-3.0-or-later
# Builds the FreeCAD addon folder (CMake target freecad_addon; the ctest fixture of freecad.addon
# runs it too):
#   cmake -DSOURCE_DIR=<repo>/bindings -DLIBRARY=<libcagekit.so> -DSONAME=<libcagekit.so.N> -DOUT=<build>/freecad_addon
#         [-DUSER_HOME=<scratch FREECAD_USER_HOME>] -P make_addon.cmake
# Layout of OUT/CageKit (copy it into FreeCAD's Mod folder, ~/.local/share/FreeCAD/Mod/ for 0.20):
#   Init.py, InitGui.py, package.xml, CageKitTools.py, CageKitGui.py, Resources/
#   cagekit/  the Python package, with libcagekit.so.N (its SONAME) next to its files (its own lookup place)
# USER_HOME: a scratch FreeCAD user folder (FREECAD_USER_HOME) is emptied, the addon copied into
# its Mod/ as a user would, and a user.cfg written that starts the GUI in the Part workbench (the
# Start page needs QtWebEngine, which the tests do without).
foreach(var SOURCE_DIR LIBRARY SONAME OUT)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "make_addon.cmake: -D${var}= is missing")
  endif()
endforeach()
if(NOT EXISTS "${LIBRARY}")
  message(FATAL_ERROR "make_addon.cmake: library ${LIBRARY} not built")
endif()
file(REMOVE_RECURSE "${OUT}/CageKit")
file(MAKE_DIRECTORY "${OUT}")
file(COPY "${SOURCE_DIR}/freecad/CageKit" DESTINATION "${OUT}"
     PATTERN "__pycache__" EXCLUDE PATTERN "*.pyc" EXCLUDE)
file(COPY "${SOURCE_DIR}/python/cagekit" DESTINATION "${OUT}/CageKit"
     PATTERN "__pycache__" EXCLUDE PATTERN "*.pyc" EXCLUDE)
# the real file (not the .so symlink chain) under the name the package looks for first
file(REAL_PATH "${LIBRARY}" real)
file(COPY_FILE "${real}" "${OUT}/CageKit/cagekit/${SONAME}")
message(STATUS "FreeCAD addon: ${OUT}/CageKit")
if(DEFINED USER_HOME)
  file(REMOVE_RECURSE "${USER_HOME}")
  file(MAKE_DIRECTORY "${USER_HOME}/Mod")
  file(COPY "${OUT}/CageKit" DESTINATION "${USER_HOME}/Mod")
  file(WRITE "${USER_HOME}/user.cfg" [=[<?xml version="1.0" encoding="UTF-8" standalone="no" ?>
<FCParameters>
  <FCParamGroup Name="Root">
    <FCParamGroup Name="BaseApp">
      <FCParamGroup Name="Preferences">
        <FCParamGroup Name="General">
          <FCText Name="AutoloadModule">PartWorkbench</FCText>
        </FCParamGroup>
      </FCParamGroup>
    </FCParamGroup>
  </FCParamGroup>
</FCParameters>
]=])
endif()
