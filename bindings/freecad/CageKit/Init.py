# SPDX-License-Identifier: GPL-3.0-or-later
# Runs at FreeCAD start-up, with or without the GUI: Draco meshes (which FreeCAD cannot read
# itself) open and import through CageKit (CageKitTools.open / insert -> a mesh object).
FreeCAD.addImportType("Draco mesh, CageKit (*.drc)", "CageKitTools")  # noqa: F821
