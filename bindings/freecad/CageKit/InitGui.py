# SPDX-License-Identifier: GPL-3.0-or-later
# The CageKit workbench (FreeCAD runs this file at GUI start-up; the commands are in CageKitGui,
# imported when the workbench is first activated, so FreeCAD starts without loading libcagekit).
# FreeCAD executes InitGui.py without __file__: the icon is found through the module path.


class CageKitWorkbench(Workbench):  # noqa: F821  (Workbench and Gui are FreeCAD's globals here)
    MenuText = "CageKit"
    ToolTip = "Scanned meshes to Catmull-Clark cages, fitted limit surfaces and STEP solids"

    def __init__(self):
        import importlib.util
        import os
        spec = importlib.util.find_spec("CageKitTools")
        if spec is not None and spec.origin:
            self.__class__.Icon = os.path.join(os.path.dirname(spec.origin), "Resources", "icons", "CageKit.svg")

    def Initialize(self):
        import CageKitGui
        self.appendToolbar("CageKit", CageKitGui.COMMANDS)
        self.appendMenu("CageKit", CageKitGui.COMMANDS)

    def Activated(self):
        return

    def Deactivated(self):
        return

    def GetClassName(self):
        return "Gui::PythonWorkbench"


Gui.addWorkbench(CageKitWorkbench())  # noqa: F821
