# SPDX-License-Identifier: GPL-3.0-or-later
"""The CageKit workbench's commands (menu "CageKit" and its toolbar), one icon each:

    CageKit_ImportScan     read a scan with the SDK (OBJ, PLY, OFF, Draco, STL) into a mesh object
    CageKit_ScanToCage     selected mesh -> parametric quad-dominant Catmull-Clark cage with creases
    CageKit_Fit            selected cage (and optionally its scan) -> fitted control points
    CageKit_LimitSurface   selected cage -> its parametric limit surface as B-spline faces, one per
                           ptex face (or one Bezier face per patch), sewn (a solid when closed)
    CageKit_ExportStep     selected limit surface or cage -> STEP file

Each command asks for its options in a task panel (Combo view > Tasks; OK runs it; the tolerance
is a length in document units, in a quantity spin box). The work runs as a Job: the SDK calls on
a worker thread (they release the GIL) while the GUI stays live, with a progress dialog whose
Cancel cancels the SDK call through the cagekit Context's progress callback; the document is
changed afterwards, on the main thread, as one undo transaction (Edit > Undo). Every failure (an
SDK error with its message, a missing library, bad input) is printed to the report view and
shown in a message box; a cancelled job changes nothing; no exception leaves a command.
"""
import os
import threading
import time

import FreeCAD
import FreeCADGui
from PySide import QtCore, QtGui

import CageKitTools as tools

ICONS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "Resources", "icons")
# The last task panel shown (its form and accept() are what the Tasks view shows and its OK calls).
last_panel = None
# The job running now (one at a time; the commands are inactive meanwhile), else None.
current_job = None
# The last job started (tests read its outcome).
last_job = None


def icon(name):
    return os.path.join(ICONS, name)


def show_error(text):
    """The host's message for a failure (the text is in the report view too)."""
    QtGui.QMessageBox.critical(FreeCADGui.getMainWindow(), "CageKit", text)


def _report(error):
    text = tools.message_of(error)
    FreeCAD.Console.PrintError(text + "\n")
    try:
        show_error(text)
    except Exception:
        pass


# --- view providers ----------------------------------------------------------------------------------
class _ViewProvider:
    """The view provider proxy of a CageKit object: its icon. Serialisable (no state)."""
    icon_file = "CageKit.svg"

    def __init__(self, vobj):
        vobj.Proxy = self

    def attach(self, vobj):
        self.Object = vobj.Object

    def getIcon(self):
        return icon(self.icon_file)

    def __getstate__(self):
        return None

    def __setstate__(self, state):
        return None


class ViewProviderCage(_ViewProvider):
    icon_file = "CageKit_ScanToCage.svg"


class ViewProviderSurface(_ViewProvider):
    icon_file = "CageKit_LimitSurface.svg"


def attach_view_provider(obj, kind):
    """Gives a new CageKit object ("cage" or "surface") its view provider proxy."""
    if getattr(obj, "ViewObject", None) is not None:
        (ViewProviderCage if kind == "cage" else ViewProviderSurface)(obj.ViewObject)


# --- jobs: SDK work on a worker thread ----------------------------------------------------------------------
class Job:
    """Runs `steps` one after the other: each is ("worker", fn) (on a worker thread: SDK calls and
    arrays only, no document access) or ("main", fn) (on the main thread); fn(value, progress)
    gets the previous step's value (None first). Then finish(value) on the main thread (the
    document changes, in one undo transaction). A QTimer polls the worker and updates a progress
    dialog and the status bar; Cancel (or cancel()) makes the cagekit progress callback return
    False, so the SDK call stops with CancelledError, and nothing is changed. Errors are reported
    (report view + message box). outcome: None while running, then "done", "cancelled" or
    "failed"."""

    def __init__(self, title, steps, finish, on_abort=None):
        self.title, self.steps, self.finish, self.on_abort = title, list(steps), finish, on_abort
        self.value = None
        self.error = None
        self.cancelled = False
        self.stage, self.fraction = "", 0.0
        self.outcome = None
        self.result = None
        self.thread = None
        self._done = threading.Event()
        self.started = time.time()
        self.dialog = QtGui.QProgressDialog(title, "Cancel", 0, 1000, FreeCADGui.getMainWindow())
        self.dialog.setWindowTitle("CageKit")
        self.dialog.setAutoClose(False)
        self.dialog.setAutoReset(False)
        self.dialog.setMinimumDuration(0)
        self.dialog.setWindowModality(QtCore.Qt.NonModal)
        self.dialog.canceled.connect(self.cancel)
        self.timer = QtCore.QTimer()
        self.timer.setInterval(50)
        self.timer.timeout.connect(self.poll)

    def start(self):
        global current_job, last_job
        if current_job is not None:
            raise tools.WorkbenchError("another CageKit job is running: wait for it or cancel it")
        current_job = last_job = self
        self.dialog.show()
        self.timer.start()
        self._advance()
        return self

    def progress(self, stage, fraction):
        """The cagekit progress callback (called on the worker thread): False cancels."""
        self.stage, self.fraction = stage, float(fraction)
        return not self.cancelled

    def cancel(self):
        self.cancelled = True

    def _work(self, fn):
        try:
            self.value = fn(self.value, self.progress)
        except BaseException as e:  # stored, reported on the main thread
            self.error = e
        finally:
            self._done.set()

    def _advance(self):
        """Runs main steps until a worker step is started, or ends the job."""
        while self.steps and not self.cancelled and self.error is None:
            where, fn = self.steps.pop(0)
            if where == "worker":
                self._done.clear()
                self.thread = threading.Thread(target=self._work, args=(fn,), name="CageKit job", daemon=True)
                self.thread.start()
                return
            try:
                self.value = fn(self.value, self.progress)
            except Exception as e:
                self.error = e
        self._end()

    def poll(self):
        if self.dialog.wasCanceled():
            self.cancelled = True
        text = self.title + (": " + self.stage if self.stage else "")
        try:
            self.dialog.setLabelText(text)
            self.dialog.setValue(int(1000 * min(max(self.fraction, 0.0), 1.0)))
            FreeCADGui.getMainWindow().statusBar().showMessage("CageKit: %s (%d%%)" % (text, 100 * self.fraction))
        except Exception:
            pass
        if self.thread is not None and not self._done.is_set():
            return
        if self.thread is not None:
            self.thread.join()
            self.thread = None
        if self.outcome is None:
            self._advance()

    def _end(self):
        global current_job
        self.timer.stop()
        try:
            self.dialog.canceled.disconnect(self.cancel)  # closing the dialog emits canceled
        except Exception:
            pass
        self.dialog.close()
        current_job = None
        seconds = time.time() - self.started
        if self.cancelled:
            self.outcome = "cancelled"
            FreeCAD.Console.PrintMessage("CageKit: %s cancelled after %.1f s; nothing changed\n" % (self.title, seconds))
        elif self.error is not None:
            self.outcome = "failed"
            _report(self.error)
        else:
            try:
                self.result = self.finish(self.value)
                self.outcome = "done"
            except Exception as e:  # never into FreeCAD's core
                self.outcome = "failed"
                _report(e)
        if self.outcome != "done" and self.on_abort is not None:
            try:
                self.on_abort(self.outcome)
            except Exception:
                pass
        try:
            FreeCADGui.getMainWindow().statusBar().showMessage("CageKit: %s %s (%.1f s)" % (self.title, self.outcome,
                                                                                          seconds), 5000)
        except Exception:
            pass

    def wait(self, timeout=600.0):
        """Processes Qt events until the job has ended (for scripts and tests); returns outcome."""
        end = time.time() + timeout
        while self.outcome is None and time.time() < end:
            QtGui.QApplication.processEvents()
            time.sleep(0.01)
        return self.outcome


def start_job(title, steps, finish, on_abort=None):
    return Job(title, steps, finish, on_abort).start()


def _alive(obj, name, doc):
    try:
        return doc.getObject(name) is obj and obj.Name == name
    except Exception:
        return False


def recompute_in_background(obj, kind):
    """tools.background_recompute: a parametric cage or surface whose inputs changed (a property
    edit, a changed scan or cage) is computed by a job on the worker thread instead of inside
    FreeCAD's recompute; its result is written when it arrives (one undo step "CageKit: recompute")
    and the document recomputed again (dependent objects follow, each by its own job). Returns
    False when a job is running already (then the recompute computes synchronously). A cancelled
    or failed job leaves the object as it was, marked touched."""
    if current_job is not None:
        return False
    doc, name = obj.Document, obj.Name
    if kind == "cage":
        pos, tris = tools.mesh_arrays(obj.Scan)
        options = tools.cage_options(obj)
        steps = [("worker", lambda _, progress: tools.cage_job(pos, tris, progress=progress, **options))]

        def write(result):
            tools.apply_cage(obj, result)
    else:
        arrays = tools.cage_arrays(obj.Cage)
        steps = _surface_steps(obj.Cage, arrays, tools.surface_options(obj, arrays))

        def write(result):
            tools.write_surface(obj, result, arrays)

    def finish(result):
        if not _alive(obj, name, doc):
            return None  # deleted meanwhile
        with tools.transaction(doc, "CageKit: recompute"):
            write(result)
            doc.recompute()
        return obj

    def abort(outcome):
        if _alive(obj, name, doc):
            obj.touch()

    start_job("Recompute %s" % obj.Label, steps, finish, abort)
    return True


tools.background_recompute = recompute_in_background


def _selection():
    return FreeCADGui.Selection.getSelection()


def _is_mesh(obj):
    return obj is not None and obj.isDerivedFrom("Mesh::Feature")


def _select(obj):
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.Selection.addSelection(obj)


# --- task panels --------------------------------------------------------------------------------------------
class _Panel:
    """A task panel with a form of fields; OK calls on_accept(values). A field's value is a bool
    (check box), an int (spin box), a float (double spin box) or a FreeCAD.Units.Quantity (a
    Gui::QuantitySpinBox in document units: its value is read back as a float in mm)."""

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
            elif isinstance(value, FreeCAD.Units.Quantity):
                w = FreeCADGui.UiLoader().createWidget("Gui::QuantitySpinBox")
                w.setProperty("unit", "mm")
                w.setProperty("minimum", float(low))
                w.setProperty("maximum", float(high))
                w.setProperty("decimals", 6)
                w.setProperty("rawValue", float(value.Value))
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
            if isinstance(w, QtGui.QCheckBox):
                out[name] = w.isChecked()
            elif isinstance(w, (QtGui.QSpinBox, QtGui.QDoubleSpinBox)):
                out[name] = w.value()
            else:
                out[name] = float(w.property("rawValue"))
        return out

    def set_values(self, **values):
        for name, value in values.items():
            w = self.widgets[name]
            if isinstance(w, QtGui.QCheckBox):
                w.setChecked(bool(value))
            elif isinstance(w, (QtGui.QSpinBox, QtGui.QDoubleSpinBox)):
                w.setValue(value)
            else:
                w.setProperty("rawValue", float(getattr(value, "Value", value)))

    def getStandardButtons(self):
        return int(QtGui.QDialogButtonBox.Ok | QtGui.QDialogButtonBox.Cancel)

    def accept(self):
        values = self.values()
        FreeCADGui.Control.closeDialog()
        try:
            self.on_accept(values)
        except Exception as e:  # never into FreeCAD's core
            _report(e)
        return True

    def reject(self):
        FreeCADGui.Control.closeDialog()
        return True


def _show(panel):
    if FreeCADGui.Control.activeDialog():
        FreeCADGui.Control.closeDialog()
    FreeCADGui.Control.showDialog(panel)
    return panel


# --- commands ----------------------------------------------------------------------------------------------
class _Command:
    name = None
    pixmap = "CageKit.svg"
    menu = tip = ""

    def GetResources(self):
        return {"Pixmap": icon(self.pixmap), "MenuText": self.menu, "ToolTip": self.tip}

    def IsActive(self):
        return current_job is None and self.active()

    def active(self):
        return True

    def Activated(self):
        try:
            self.activated()
        except Exception as e:  # never into FreeCAD's core
            _report(e)


class ImportScan(_Command):
    name = "CageKit_ImportScan"
    pixmap = "CageKit_ImportScan.svg"
    menu = "Import scan..."
    tip = "Read a scanned mesh (OBJ, PLY, OFF, Draco, STL) with CageKit into a mesh object"

    def activated(self):
        path, _ = QtGui.QFileDialog.getOpenFileName(FreeCADGui.getMainWindow(), "Import scan", "",
                                                    "Meshes (*.obj *.ply *.off *.drc *.stl);;All files (*)")
        if not path:
            return
        doc = FreeCAD.ActiveDocument or FreeCAD.newDocument()

        def finish(value):
            obj = tools.add_scan(doc, *value)
            _select(obj)
            FreeCADGui.SendMsgToActiveView("ViewFit")
            return obj

        start_job("Import scan", [("worker", lambda _, progress: tools.read_scan_job(path, progress))], finish)


class ScanToCage(_Command):
    name = "CageKit_ScanToCage"
    pixmap = "CageKit_ScanToCage.svg"
    menu = "Scan to cage"
    tip = ("Simplify the selected mesh to a parametric quad-dominant Catmull-Clark cage whose edges "
           "follow its structure, with crease edges")

    def active(self):
        sel = _selection()
        return len(sel) == 1 and _is_mesh(sel[0])

    def activated(self):
        sel = _selection()
        if len(sel) != 1 or not _is_mesh(sel[0]):
            raise tools.WorkbenchError("select one mesh object")
        scan = sel[0]

        def accept(v):
            pos, tris = tools.mesh_arrays(scan)

            def work(_, progress):
                return tools.cage_job(pos, tris, faces=v["faces"], crease_angle=v["crease_angle"], passes=v["passes"],
                                      keep_crease_vertices=v["keep_crease_vertices"], progress=progress)

            def finish(result):
                cage = tools.add_cage(scan, result)
                scan.ViewObject.Visibility = False
                _select(cage)
                return cage

            start_job("Scan to cage", [("worker", work)], finish)

        _show(_Panel("CageKit: scan to cage", [
            ("faces", "Faces", 200, 1, 10000000,
             "Faces of the simplified mesh (the finest level with at most this many); splitting its "
             "polygons into quads gives the cage more faces"),
            ("crease_angle", "Crease angle (deg)", 30.0, 0.0, 180.0,
             "Cage edges whose dihedral angle exceeds this become creases"),
            ("passes", "Fitting passes", 0, 0, 100, "Fit right away (0: use Fit afterwards)"),
            ("keep_crease_vertices", "Keep crease vertices", False, 0, 1, "Do not move crease vertices when fitting"),
        ], accept))


def _surface_steps(cage_obj, arrays, options):
    """The steps of a limit surface: SDK + Part faces (worker), sewing (main: FreeCAD's sewing
    goes through a scratch document), solid + BRepCheck (worker)."""
    return [("worker", lambda _, progress: tools.surface_faces(
                tools.surface_sdk(arrays, samples=0, progress=progress, **options))),
            ("main", lambda faces, progress: tools.surface_sew(faces)),
            ("worker", lambda sewn, progress: tools.surface_solid(sewn))]


class Fit(_Command):
    name = "CageKit_Fit"
    pixmap = "CageKit_Fit.svg"
    menu = "Fit"
    tip = ("Fit the selected cage's limit surface to its scan (select the cage, or the cage and a mesh); "
           "its limit surface follows")

    def active(self):
        return any(tools.is_cage(o) for o in _selection())

    def activated(self):
        sel = _selection()
        cages = [o for o in sel if tools.is_cage(o)]
        meshes = [o for o in sel if _is_mesh(o)]
        if len(cages) != 1 or len(meshes) > 1:
            raise tools.WorkbenchError("select one cage (and at most one mesh: the scan)")
        cage, scan = cages[0], (meshes[0] if meshes else getattr(cages[0], "Scan", None))
        if scan is None:
            raise tools.WorkbenchError("cage %r has no scan: select the scan too" % cage.Label)

        def accept(v):
            pos, tris = tools.mesh_arrays(scan)
            arrays = tools.cage_arrays(cage)
            surface = tools.surface_of(cage)
            length = float(surface.Tolerance.Value) if surface is not None else None
            surface_args = (str(surface.Mode), int(surface.MaxLevel), int(surface.MaxDepth)) if surface else None

            def fit(_, progress):
                return tools.fit_job(pos, tris, arrays, v["passes"], v["keep_crease_vertices"], progress)

            def follow(value, progress):
                # The cage's limit surface, recomputed here on the worker thread (not in the
                # recompute after the fit, on the main thread).
                data, report = value
                if surface is None:
                    return data, report, None
                mode, max_level, max_depth = surface_args
                diag = tools.bbox_diagonal(data)
                stage = tools.surface_sdk(data, length / diag, mode, max_level, max_depth, 0, progress)
                return data, report, tools.surface_faces(stage)

            def sew(value, progress):
                data, report, faces = value
                return data, report, (tools.surface_sew(faces) if faces is not None else None)

            def solid(value, progress):
                data, report, sewn = value
                return data, report, (tools.surface_solid(sewn) if sewn is not None else None)

            def finish(value):
                data, report, result = value
                tools.apply_fit(cage, scan, data, report, v["passes"],
                                surfaces=[(surface, result)] if result is not None else ())
                return report

            start_job("Fit", [("worker", fit), ("worker", follow), ("main", sew), ("worker", solid)], finish)

        _show(_Panel("CageKit: fit", [
            ("passes", "Fitting passes", 5, 1, 100, "Parameterisation + least-squares passes"),
            ("keep_crease_vertices", "Keep crease vertices", False, 0, 1, "Do not move crease vertices"),
        ], accept))


def _limit_fields(length, diagonal):
    return [("tolerance", "Tolerance", FreeCAD.Units.Quantity(length, FreeCAD.Units.Length), 0.0,
             max(diagonal, 1.0),
             "Largest distance allowed between an approximated face and the limit surface, in document "
             "units (the SDK gets it as a fraction of the cage's bounding-box diagonal, %.6g mm)" % diagonal),
            ("max_level", "Max knot level", 5, 1, 7,
             "B-spline faces: the finest knot spacing tried next to extraordinary vertices "
             "(up to 2^level spans per cage edge)"),
            ("per_patch", "One Bezier face per patch", False, 0, 1,
             "The first mode: one bicubic face per SDK patch (thousands of faces) instead of one "
             "B-spline face per ptex face"),
            ("max_depth", "Max depth (per patch)", 8, 0, 12,
             "One face per patch: quadtree splits of a region that is not one polynomial")]


def surface_job(cage, length=None, mode="bspline", max_level=5, max_depth=8, then=(), on_done=None):
    """Starts the job that makes / updates the cage's limit surface (tolerance `length` in
    document units, default 1e-4 of the diagonal); `then`: more steps after it (they get the
    surface object); on_done(value) finishes."""
    if mode not in tools.MODES:
        raise tools.WorkbenchError("mode must be one of %s, not %r" % (", ".join(tools.MODES), mode))
    if length is None:
        arrays, options, length = tools.surface_request(cage, 1e-4, mode, max_level, max_depth)
    else:
        arrays, options, length = tools.surface_request(cage, mode=mode, max_level=max_level, max_depth=max_depth,
                                                        length=length)

    def apply(result, progress):
        return tools.apply_surface(cage, result, arrays, length, max_level, max_depth)

    steps = _surface_steps(cage, arrays, options)
    if then:
        steps = steps + [("main", apply)] + list(then)
        return start_job("Limit surface", steps, on_done or (lambda value: value))
    return start_job("Limit surface", steps, lambda result: (on_done or (lambda s: s))(apply(result, None)))


class LimitSurface(_Command):
    name = "CageKit_LimitSurface"
    pixmap = "CageKit_LimitSurface.svg"
    menu = "Limit surface"
    tip = ("Make the selected cage's parametric limit surface as B-spline faces (one per ptex face, or one "
           "Bezier face per patch), sewn into a solid when closed")

    def active(self):
        return any(tools.is_cage(o) for o in _selection())

    def activated(self):
        cages = [o for o in _selection() if tools.is_cage(o)]
        if len(cages) != 1:
            raise tools.WorkbenchError("select one cage")
        cage = cages[0]
        diagonal = tools.bbox_diagonal(tools.cage_arrays(cage))
        existing = tools.surface_of(cage)
        length = float(existing.Tolerance.Value) if existing is not None else 1e-4 * diagonal

        def done(surface):
            cage.ViewObject.Visibility = False
            _select(surface)
            return surface

        def accept(v):
            surface_job(cage, length=v["tolerance"], mode="patches" if v["per_patch"] else "bspline",
                        max_level=v["max_level"], max_depth=v["max_depth"], on_done=done)

        _show(_Panel("CageKit: limit surface", _limit_fields(length, diagonal), accept))


class ExportStep(_Command):
    name = "CageKit_ExportStep"
    pixmap = "CageKit_ExportStep.svg"
    menu = "Export STEP..."
    tip = ("Save the selected limit surface (or the selected cage's, made with the default options "
           "when it has none) as a STEP file")

    def active(self):
        sel = _selection()
        return len(sel) == 1 and (tools.is_cage(sel[0]) or tools.is_limit_surface(sel[0]))

    def activated(self):
        sel = _selection()
        if len(sel) != 1 or not (tools.is_cage(sel[0]) or tools.is_limit_surface(sel[0])):
            raise tools.WorkbenchError("select one cage or limit surface")
        obj = sel[0]
        surface = tools.surface_of(obj) if tools.is_cage(obj) else obj
        label = surface.Label if surface is not None else obj.Label + "_surface"
        start = os.path.join(os.path.expanduser("~"), label + ".step")
        path, _ = QtGui.QFileDialog.getSaveFileName(FreeCADGui.getMainWindow(), "Export STEP", start,
                                                    "STEP (*.step *.stp)")
        if not path:
            return
        if not path.lower().endswith((".step", ".stp")):
            path += ".step"

        def shape_of(s, progress):
            if s.Shape.isNull() or not s.Shape.Faces:
                raise tools.WorkbenchError("nothing to export: the shape has no faces")
            return s.Shape.copy()

        write = ("worker", lambda shape, progress: tools.export_step(shape, path))
        if surface is None:  # the cage's surface first, with the defaults (one undo step)
            surface_job(obj, then=[("main", shape_of), write])
        else:
            start_job("Export STEP", [("main", lambda _, progress: shape_of(surface, progress)), write],
                      lambda p: p)


COMMANDS = [c.name for c in (ImportScan, ScanToCage, Fit, LimitSurface, ExportStep)]
for _cls in (ImportScan, ScanToCage, Fit, LimitSurface, ExportStep):
    FreeCADGui.addCommand(_cls.name, _cls())
