# SPDX-License-Identifier: GPL-3.0-or-later
"""The CageKit workbench's commands (menu "CageKit" and its toolbar):

    CageKit_ImportScan     read a scan with the SDK (OBJ, PLY, OFF, Draco, STL) into a mesh object
    CageKit_ScanToCage     selected mesh -> quad-dominant Catmull-Clark cage with creases
    CageKit_Fit            selected cage (and optionally its scan) -> fitted control points
    CageKit_LimitSurface   selected cage -> its limit surface as B-spline faces, one per ptex face (or
                           one Bezier face per patch), sewn (a solid when closed)
    CageKit_ExportStep     selected limit surface or cage -> STEP file

Each command asks for its options in a task panel (Combo view > Tasks; OK runs it) and calls
CageKitTools. Every failure (an SDK error with its message, a missing library, bad input)
is printed to the report view and shown in a message box; no exception leaves a command.
"""
import os

import FreeCAD
import FreeCADGui
from PySide import QtGui

import CageKitTools as tools

ICONS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "Resources", "icons")
# The last task panel shown (its form and accept() are what the Tasks view shows and its OK calls).
last_panel = None


def show_error(text):
    """The host's message for a failure (the text is in the report view too)."""
    QtGui.QMessageBox.critical(FreeCADGui.getMainWindow(), "CageKit", text)


def run(action, *args, **kwargs):
    """action(...) with FreeCAD's progress indicator; errors reported (console + message box)."""
    progress = tools.Progress("CageKit")
    try:
        return tools.run_reported(action, *args, report=show_error, progress=progress, **kwargs)
    finally:
        progress.stop()


def _selection():
    return FreeCADGui.Selection.getSelection()


def _is_mesh(obj):
    return obj is not None and obj.isDerivedFrom("Mesh::Feature")


class _Panel:
    """A task panel with a form of numeric / boolean fields; OK calls on_accept(values)."""

    def __init__(self, title, fields, on_accept):
        global last_panel
        self.form = QtGui.QWidget()
        self.form.setWindowTitle(title)
        layout = QtGui.QFormLayout(self.form)
        self.widgets = {}
        for name, label, value, low, high, tip in fields:
            if isinstance(value, bool):
                w = QtGui.QCheckBox()
                w.setChecked(value)
            elif isinstance(value, int):
                w = QtGui.QSpinBox()
                w.setRange(low, high)
                w.setValue(value)
            else:
                w = QtGui.QDoubleSpinBox()
                w.setDecimals(8 if high <= 1.0 else 2)
                w.setRange(low, high)
                w.setSingleStep(1e-5 if high <= 1.0 else 1.0)
                w.setValue(value)
            w.setToolTip(tip)
            layout.addRow(label, w)
            self.widgets[name] = w
        self.on_accept = on_accept
        last_panel = self

    def values(self):
        out = {}
        for name, w in self.widgets.items():
            out[name] = w.isChecked() if isinstance(w, QtGui.QCheckBox) else w.value()
        return out

    def set_values(self, **values):
        for name, value in values.items():
            w = self.widgets[name]
            if isinstance(w, QtGui.QCheckBox):
                w.setChecked(bool(value))
            else:
                w.setValue(value)

    def getStandardButtons(self):
        return int(QtGui.QDialogButtonBox.Ok | QtGui.QDialogButtonBox.Cancel)

    def accept(self):
        values = self.values()
        FreeCADGui.Control.closeDialog()
        try:
            self.on_accept(values)
        except Exception as e:  # never into FreeCAD's core
            text = tools.message_of(e)
            FreeCAD.Console.PrintError(text + "\n")
            show_error(text)
        return True

    def reject(self):
        FreeCADGui.Control.closeDialog()
        return True


def _show(panel):
    if FreeCADGui.Control.activeDialog():
        FreeCADGui.Control.closeDialog()
    FreeCADGui.Control.showDialog(panel)
    return panel


class _Command:
    name = None
    pixmap = "CageKit.svg"
    menu = tip = ""

    def GetResources(self):
        return {"Pixmap": os.path.join(ICONS, self.pixmap), "MenuText": self.menu, "ToolTip": self.tip}

    def Activated(self):
        try:
            self.activated()
        except Exception as e:  # never into FreeCAD's core
            text = tools.message_of(e)
            FreeCAD.Console.PrintError(text + "\n")
            show_error(text)


class ImportScan(_Command):
    name = "CageKit_ImportScan"
    menu = "Import scan..."
    tip = "Read a scanned mesh (OBJ, PLY, OFF, Draco, STL) with CageKit into a mesh object"

    def IsActive(self):
        return True

    def activated(self):
        path, _ = QtGui.QFileDialog.getOpenFileName(FreeCADGui.getMainWindow(), "Import scan", "",
                                                    "Meshes (*.obj *.ply *.off *.drc *.stl);;All files (*)")
        if path:
            doc = FreeCAD.ActiveDocument or FreeCAD.newDocument()
            obj = run(lambda progress: tools.import_scan(path, doc))
            if obj is not None:
                FreeCADGui.Selection.clearSelection()
                FreeCADGui.Selection.addSelection(obj)
                FreeCADGui.SendMsgToActiveView("ViewFit")


class ScanToCage(_Command):
    name = "CageKit_ScanToCage"
    menu = "Scan to cage"
    tip = ("Simplify the selected mesh to a quad-dominant Catmull-Clark cage whose edges follow its "
           "structure, with crease edges")

    def IsActive(self):
        sel = _selection()
        return len(sel) == 1 and _is_mesh(sel[0])

    def activated(self):
        sel = _selection()
        if len(sel) != 1 or not _is_mesh(sel[0]):
            raise tools.WorkbenchError("select one mesh object")
        scan = sel[0]

        def accept(v):
            cage = run(tools.scan_to_cage, scan, faces=v["faces"], crease_angle=v["crease_angle"],
                       passes=v["passes"], keep_crease_vertices=v["keep_crease_vertices"])
            if cage is not None:
                scan.ViewObject.Visibility = False
                FreeCADGui.Selection.clearSelection()
                FreeCADGui.Selection.addSelection(cage)

        _show(_Panel("CageKit: scan to cage", [
            ("faces", "Faces", 200, 1, 10000000,
             "Faces of the simplified mesh (the finest level with at most this many); splitting its "
             "polygons into quads gives the cage more faces"),
            ("crease_angle", "Crease angle (deg)", 30.0, 0.0, 180.0,
             "Cage edges whose dihedral angle exceeds this become creases"),
            ("passes", "Fitting passes", 0, 0, 100, "Fit right away (0: use Fit afterwards)"),
            ("keep_crease_vertices", "Keep crease vertices", False, 0, 1, "Do not move crease vertices when fitting"),
        ], accept))


class Fit(_Command):
    name = "CageKit_Fit"
    menu = "Fit"
    tip = "Fit the selected cage's limit surface to its scan (select the cage, or the cage and a mesh)"

    def IsActive(self):
        return any(tools.is_cage(o) for o in _selection())

    def activated(self):
        sel = _selection()
        cages = [o for o in sel if tools.is_cage(o)]
        meshes = [o for o in sel if _is_mesh(o)]
        if len(cages) != 1 or len(meshes) > 1:
            raise tools.WorkbenchError("select one cage (and at most one mesh: the scan)")
        cage, scan = cages[0], (meshes[0] if meshes else None)

        def accept(v):
            run(tools.fit_cage, cage, scan, passes=v["passes"], keep_crease_vertices=v["keep_crease_vertices"])

        _show(_Panel("CageKit: fit", [
            ("passes", "Fitting passes", 5, 1, 100, "Parameterisation + least-squares passes"),
            ("keep_crease_vertices", "Keep crease vertices", False, 0, 1, "Do not move crease vertices"),
        ], accept))


def _limit_fields():
    return [("tolerance", "Tolerance (of the diagonal)", 1e-4, 1e-8, 1.0,
             "Largest distance allowed between an approximated surface and the limit surface, as a "
             "fraction of the cage's bounding-box diagonal"),
            ("max_level", "Max knot level", 5, 1, 7,
             "B-spline faces: the finest knot spacing tried next to extraordinary vertices "
             "(up to 2^level spans per cage edge)"),
            ("per_patch", "One Bezier face per patch", False, 0, 1,
             "The first mode: one bicubic face per SDK patch (thousands of faces) instead of one "
             "B-spline face per ptex face"),
            ("max_depth", "Max depth (per patch)", 8, 0, 12,
             "One face per patch: quadtree splits of a region that is not one polynomial")]


class LimitSurface(_Command):
    name = "CageKit_LimitSurface"
    menu = "Limit surface"
    tip = ("Make the selected cage's limit surface as B-spline faces (one per ptex face, or one Bezier "
           "face per patch), sewn into a solid when closed")

    def IsActive(self):
        return any(tools.is_cage(o) for o in _selection())

    def activated(self):
        cages = [o for o in _selection() if tools.is_cage(o)]
        if len(cages) != 1:
            raise tools.WorkbenchError("select one cage")
        cage = cages[0]

        def accept(v):
            surface = run(tools.limit_surface, cage, tolerance=v["tolerance"], max_depth=v["max_depth"],
                          mode="patches" if v["per_patch"] else "bspline", max_level=v["max_level"])
            if surface is not None:
                cage.ViewObject.Visibility = False
                FreeCADGui.Selection.clearSelection()
                FreeCADGui.Selection.addSelection(surface)

        _show(_Panel("CageKit: limit surface", _limit_fields(), accept))


class ExportStep(_Command):
    name = "CageKit_ExportStep"
    menu = "Export STEP..."
    tip = ("Save the selected limit surface (or the selected cage's, made with the default options "
           "when it has none) as a STEP file")

    def IsActive(self):
        sel = _selection()
        return len(sel) == 1 and (tools.is_cage(sel[0]) or tools.is_limit_surface(sel[0]))

    def activated(self):
        sel = _selection()
        if len(sel) != 1 or not (tools.is_cage(sel[0]) or tools.is_limit_surface(sel[0])):
            raise tools.WorkbenchError("select one cage or limit surface")
        obj = sel[0]
        if tools.is_cage(obj):
            existing = [o for o in obj.Document.Objects if tools.is_limit_surface(o) and o.Cage is obj]
            obj = existing[0] if existing else run(tools.limit_surface, obj)
            if obj is None:
                return
        start = os.path.join(os.path.expanduser("~"), obj.Label + ".step")
        path, _ = QtGui.QFileDialog.getSaveFileName(FreeCADGui.getMainWindow(), "Export STEP", start,
                                                    "STEP (*.step *.stp)")
        if path:
            if not path.lower().endswith((".step", ".stp")):
                path += ".step"
            run(lambda progress: tools.export_step(obj, path))


COMMANDS = [c.name for c in (ImportScan, ScanToCage, Fit, LimitSurface, ExportStep)]
for _cls in (ImportScan, ScanToCage, Fit, LimitSurface, ExportStep):
    FreeCADGui.addCommand(_cls.name, _cls())
