# SPDX-License-Identifier: GPL-3.0-or-later
"""The documented click path through the CageKit workbench in FreeCAD's real GUI (ctest
freecad.gui, label freecad), run with Qt's offscreen platform:

    QT_QPA_PLATFORM=offscreen FREECAD_USER_HOME=<scratch with Mod/CageKit> freecad test_freecad_gui.py

The addon is the installed folder (make_addon.cmake -DUSER_HOME=...), found by FreeCAD in the
scratch user folder's Mod/. FreeCAD runs this file as a macro once its main window is up.
Workbench CageKit -> Import scan (fandisk, or a generated block) -> select it -> Scan to cage
(task panel: Faces 200, OK) -> Fit (OK) -> Limit surface (tolerance 1e-3, B-spline faces, OK) -> Export STEP
(file dialog). A file dialog cannot be
clicked offscreen: QFileDialog's static functions answer with the test's paths; message boxes
are recorded instead of shown (they would block). Checks the objects, the STEP file (one face
per patch), and that bad input (a corrupt file, an empty mesh, a NaN vertex) ends in a CageKit
message box with FreeCAD still working. The process exits with 0 or 1 (os._exit: the GUI's event
loop would otherwise keep running).
"""
import os
import sys
import tempfile
import time
import traceback

import FreeCAD
import FreeCADGui

failures = []


def check(cond, what):
    print(("ok    " if cond else "FAIL  ") + what, flush=True)
    if not cond:
        failures.append(what)


def main(out_dir):
    from PySide import QtGui
    import Mesh
    t0 = time.time()
    FreeCADGui.activateWorkbench("CageKitWorkbench")
    check(FreeCADGui.activeWorkbench().name() == "CageKitWorkbench", "workbench CageKit activated")
    import CageKitGui
    mod = os.path.realpath(os.path.join(FreeCAD.getUserAppDataDir(), "Mod", "CageKit"))
    check(os.path.realpath(CageKitGui.__file__).startswith(mod + os.sep),
          "the workbench is the installed addon (%s)" % CageKitGui.__file__)
    commands = set(FreeCADGui.listCommands())
    check(all(c in commands for c in CageKitGui.COMMANDS), "commands registered: %s" % ", ".join(CageKitGui.COMMANDS))
    mw = FreeCADGui.getMainWindow()
    menu = [a for a in mw.menuBar().actions() if a.text().replace("&", "") == "CageKit"]
    items = [a.text().replace("&", "") for a in menu[0].menu().actions()] if menu else []
    check(len(menu) == 1 and len(items) == len(CageKitGui.COMMANDS),
          "menu CageKit in the menu bar: %s" % ", ".join(items))
    check_icons(CageKitGui, mw)

    boxes = []
    QtGui.QMessageBox.critical = staticmethod(lambda parent, title, text, *a, **k: boxes.append((title, text)))
    answers = {}
    QtGui.QFileDialog.getOpenFileName = staticmethod(lambda *a, **k: (answers["open"], ""))
    QtGui.QFileDialog.getSaveFileName = staticmethod(lambda *a, **k: (answers["save"], ""))

    doc = FreeCAD.newDocument("ClickPath")
    shared = os.environ.get("CAGEKIT_SHARED_MESHES") or os.path.join(os.path.dirname(__file__), "..", "..", "..",
                                                                      "..", "shared", "meshes")
    scan_path = os.path.join(shared, "fandisk.obj")
    if not os.path.isfile(scan_path):
        print("scan: %s absent; using a generated block (written as OBJ)" % scan_path)
        scan_path = os.path.join(out_dir, "block.obj")
        write_block(scan_path)

    def wait():
        """Waits for the job a command started (the SDK on a worker thread, the GUI live)."""
        job = CageKitGui.current_job
        if job is not None:
            job.wait()
        FreeCADGui.updateGui()
        return job

    def run(name):
        CageKitGui.last_job = None
        FreeCADGui.runCommand(name)
        FreeCADGui.updateGui()
        wait()

    def accept(**values):
        panel, CageKitGui.last_panel = CageKitGui.last_panel, None
        ok = panel is not None and FreeCADGui.Control.activeDialog()
        if panel is not None:
            panel.set_values(**values)
            panel.accept()
        FreeCADGui.updateGui()
        wait()
        return ok

    # Import scan (File dialog) -> a mesh object, selected
    answers["open"] = scan_path
    run("CageKit_ImportScan")
    meshes = [o for o in doc.Objects if o.isDerivedFrom("Mesh::Feature")]
    check(len(meshes) == 1 and FreeCADGui.Selection.getSelection() == meshes[:1] and not boxes,
          "Import scan: mesh object %r (%d facets), selected" % (meshes[0].Label if meshes else None,
                                                                 meshes[0].Mesh.CountFacets if meshes else 0))
    scan = meshes[0]
    # Scan to cage -> task panel -> OK, cancelled once mid-way (Cancel of the progress dialog)
    run("CageKit_ScanToCage")
    panel, CageKitGui.last_panel = CageKitGui.last_panel, None
    panel.set_values(faces=200)
    panel.accept()
    job = CageKitGui.current_job
    while job is not None and not job.stage and job.outcome is None:
        QtGui.QApplication.processEvents()
        time.sleep(0.005)
    t = time.time()
    stage = job.stage if job else None
    if job is not None:
        [b for b in job.dialog.findChildren(QtGui.QPushButton) if b.text().replace("&", "") == "Cancel"][0].click()
        job.wait()
    check(job is not None and job.outcome == "cancelled" and job.stage and len(doc.Objects) == 1 and not boxes
          and doc.UndoCount == 1,
          "Scan to cage cancelled during the SDK call (stage %r): took effect in %.2f s, nothing made, no undo "
          "step, no message box (outcome %s, %d objects, undo %s, boxes %s)"
          % (stage, time.time() - t, job.outcome if job else None, len(doc.Objects), doc.UndoNames, boxes))
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.Selection.addSelection(scan)
    run("CageKit_ScanToCage")
    t = time.time()
    gaps = []
    CageKitGui.last_panel.set_values(faces=200)
    CageKitGui.last_panel.accept()
    job, last = CageKitGui.current_job, time.time()
    ticks = 0
    while job is not None and job.outcome is None:
        QtGui.QApplication.processEvents()
        now = time.time()
        gaps.append(now - last)
        last = now
        ticks += 1
        time.sleep(0.01)
    check(job is not None and job.outcome == "done" and ticks > 10 and max(gaps) < 2.0,
          "Scan to cage ran as a job: %.1f s, the event loop turned %d times meanwhile (largest gap %.2f s)"
          % (time.time() - t, ticks, max(gaps) if gaps else -1))
    cages = [o for o in doc.Objects if "ControlPoints" in o.PropertiesList]
    # The journey may use a finer target than asked (TargetFaces: while the limit strays or
    # self-intersects more than the scan); the level has at most that many faces.
    target = cages[0].TargetFaces if cages else 0
    check(len(cages) == 1 and target >= 200 and cages[0].LevelFaces <= target and
          cages[0].LevelFaces > 0.75 * target and not boxes,
          "Scan to cage: %r, level of %d faces (target %d for 200 asked), %d cage faces, selected"
          % (cages[0].Label if cages else None, cages[0].LevelFaces if cages else 0, target,
             len(cages[0].FaceSizes) if cages else 0))
    cage = cages[0]
    check(FreeCADGui.Selection.getSelection() == [cage] and not scan.ViewObject.Visibility,
          "the cage is selected and the scan hidden")
    check(type(cage.Proxy).__name__ == "CageProxy" and type(cage.ViewObject.Proxy).__name__ == "ViewProviderCage"
          and cage.ViewObject.Proxy.getIcon().endswith("CageKit_ScanToCage.svg"),
          "the cage is parametric (CageProxy) with its view provider and icon")
    name = cage.Name
    FreeCADGui.runCommand("Std_Undo")
    undone = doc.getObject(name) is None
    FreeCADGui.runCommand("Std_Redo")
    cage = doc.getObject(name)
    check(undone and cage is not None and type(cage.Proxy).__name__ == "CageProxy" and doc.UndoNames[:1] ==
          ["CageKit: scan to cage"], "Edit > Undo removes the cage, Redo brings it back (%s)" % doc.UndoNames)
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.Selection.addSelection(cage)
    # Fit -> OK
    run("CageKit_Fit")
    check(accept(passes=3), "Fit shows its task panel")
    check(cage.FitPasses >= 1 and 0 < cage.FitRmsRel < 1e-3 and not boxes,
          "Fit: %d passes, rms %.2e of the diagonal" % (cage.FitPasses, cage.FitRmsRel))
    fitted = [tuple(p) for p in cage.ControlPoints]
    FreeCADGui.runCommand("Std_Undo")
    undone = [tuple(p) for p in cage.ControlPoints] != fitted and cage.FitAfter == 0
    FreeCADGui.runCommand("Std_Redo")
    check(undone and [tuple(p) for p in cage.ControlPoints] == fitted and cage.FitAfter == 3,
          "Edit > Undo reverts the fit's control points, Redo restores them")
    # Limit surface -> task panel (tolerance 1e-3: fewer patches than the default 1e-4) -> OK
    t = time.time()
    run("CageKit_LimitSurface")
    import CageKitTools as tools
    diag = tools.bbox_diagonal(tools.cage_arrays(cage))
    panel = CageKitGui.last_panel
    spin = panel.widgets["tolerance"] if panel else None
    check(spin is not None and spin.metaObject().className() == "Gui::QuantitySpinBox"
          and abs(float(spin.property("rawValue")) - 1e-4 * diag) < 1e-9 * diag,
          "the tolerance is a Gui::QuantitySpinBox in mm (default 1e-4 of the diagonal: %s)"
          % (spin.property("value") if spin is not None else None))
    check(accept(tolerance=1e-3 * diag, max_depth=8), "Limit surface shows its task panel")
    surfaces = [o for o in doc.Objects if "PatchCount" in o.PropertiesList]
    check(len(surfaces) == 1 and abs(surfaces[0].ToleranceRel - 1e-3) < 1e-6
          and abs(surfaces[0].Tolerance.Value - 1e-3 * diag) < 1e-6 * diag and surfaces[0].Closed and surfaces[0].Valid
          and surfaces[0].Mode == "bspline" and surfaces[0].Shape.ShapeType == "Solid"
          and FreeCADGui.Selection.getSelection() == surfaces[0:1] and not boxes,
          "Limit surface: %r, mode %s (the panel's default), %d faces, closed valid solid, selected (%.1f s)"
          % (surfaces[0].Label if surfaces else None, surfaces[0].Mode if surfaces else None,
             surfaces[0].PatchCount if surfaces else 0, time.time() - t))
    # Export STEP -> file dialog (no extension typed: .step is added)
    step = os.path.join(out_dir, "fandisk")
    answers["save"] = step
    t = time.time()
    run("CageKit_ExportStep")
    check(os.path.isfile(step + ".step") and not boxes,
          "Export STEP: %s.step written (%.1f s)" % (step, time.time() - t))
    import Part
    back = Part.read(step + ".step")
    check(surfaces and len(back.Faces) == surfaces[0].PatchCount and (not surfaces[0].Closed or len(back.Solids) == 1),
          "the STEP file: %d faces == %d patches, %d solid(s)" % (len(back.Faces), surfaces[0].PatchCount,
                                                                len(back.Solids)))

    # bad input -> a CageKit message box, FreeCAD goes on
    def expect_box(what, words):
        ok = len(boxes) == 1 and all(w.lower() in boxes[0][1].lower() for w in words)
        check(ok, "%s -> message box %r" % (what, boxes[0][1] if boxes else None))
        boxes.clear()

    count = len(doc.Objects)
    corrupt = os.path.join(out_dir, "corrupt.obj")
    with open(corrupt, "w") as f:
        f.write("v 0 0 0\nv 1 0 0\nf 1 2 7\n")
    answers["open"] = corrupt
    run("CageKit_ImportScan")
    expect_box("Import scan of a corrupt OBJ", ["CageKit", "corrupt.obj"])
    empty = doc.addObject("Mesh::Feature", "empty")
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.Selection.addSelection(empty)
    run("CageKit_ScanToCage")
    accept(faces=10)
    expect_box("Scan to cage of an empty mesh", ["CageKit", "no faces"])
    nan = doc.addObject("Mesh::Feature", "nan")
    V = FreeCAD.Vector
    nan.Mesh = Mesh.Mesh(([V(0, 0, 0), V(1, 0, 0), V(0, 1, 0), V(0, 0, float("nan"))],
                          [(0, 2, 1), (0, 1, 3), (1, 2, 3), (0, 3, 2)]))
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.Selection.addSelection(nan)
    run("CageKit_ScanToCage")
    accept(faces=2)
    expect_box("Scan to cage of a mesh with a NaN vertex", ["CageKit", "finite"])
    check(len(doc.Objects) == count + 2, "no objects made by the failed commands")
    check(CageKitGui.current_job is None and all(FreeCADGui.isCommandActive(c) for c in ("CageKit_ImportScan",)),
          "no job left running; the commands are active again")
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.Selection.addSelection(scan)
    run("CageKit_ScanToCage")
    accept(faces=50)
    check(len(doc.Objects) == count + 3 and not boxes, "FreeCAD and the workbench still work after the errors")

    # Export STEP of a cage without a surface: the surface job (defaults), then the STEP file
    small = doc.Objects[-1]
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.Selection.addSelection(small)
    answers["save"] = os.path.join(out_dir, "small.step")
    run("CageKit_ExportStep")
    small_surface = tools.surface_of(small)
    check(small_surface is not None and small_surface.Valid and abs(small_surface.ToleranceRel - 1e-4) < 1e-9
          and os.path.isfile(answers["save"]) and doc.UndoNames[0] == "CageKit: limit surface" and not boxes,
          "Export STEP of a cage without a surface: %r made (1e-4 of the diagonal, one undo step), STEP written"
          % (small_surface.Label if small_surface else None))
    # Fit of a cage with a surface: the surface follows inside the job (worker), not in the recompute
    calls = []
    original = tools.surface_shape
    tools.surface_shape = lambda *a, **k: calls.append(1) or original(*a, **k)
    key = small_surface.InputKey if small_surface else None
    try:
        FreeCADGui.Selection.clearSelection()
        FreeCADGui.Selection.addSelection(small)
        run("CageKit_Fit")
        accept(passes=1)
    finally:
        tools.surface_shape = original
    check(small_surface is not None and small_surface.InputKey != key and not calls and small_surface.Valid
          and small_surface.InputKey == tools.surface_input_key(small_surface) and doc.UndoNames[0] == "CageKit: fit",
          "Fit of a cage with a surface: the surface recomputed in the job, none in FreeCAD's recompute")
    FreeCADGui.runCommand("Std_Undo")
    check(small_surface.InputKey == key and small.FitAfter == 0,
          "Edit > Undo reverts the fit and its surface in one step")

    # A property edit: FreeCAD's recompute starts a job (worker) instead of computing in place;
    # the cage's result then recomputes its surface by a second job
    faces_before, patches_before = len(small.FaceSizes), small_surface.PatchCount
    small.Faces = 30
    t = time.time()
    doc.recompute()
    t_recompute = time.time() - t
    first = CageKitGui.current_job
    wait()
    second = CageKitGui.current_job
    wait()
    check(first is not None and second is not None and first.outcome == second.outcome == "done"
          and t_recompute < 1.0 and small.Faces == 30 and len(small.FaceSizes) != faces_before
          and small.InputKey == tools.cage_input_key(small) and small_surface.PatchCount != patches_before
          and small_surface.InputKey == tools.surface_input_key(small_surface) and small_surface.Valid
          and doc.UndoNames[0] == "CageKit: recompute" and not boxes,
          "cage.Faces 50 -> 30 + recompute: returned in %.2f s, jobs %r then %r: %d -> %d cage faces, %d -> %d "
          "surface faces" % (t_recompute, first.title if first else None, second.title if second else None,
                             faces_before, len(small.FaceSizes), patches_before, small_surface.PatchCount))
    # Save and open (a copy: closing a document's 3D view crashes Coin under the offscreen platform):
    # the proxies and the view providers (icons) come back
    import shutil
    fcstd = os.path.join(out_dir, "clickpath.FCStd")
    doc.saveAs(fcstd)
    names = (cage.Name, small.Name, small_surface.Name)
    shutil.copy(fcstd, os.path.join(out_dir, "clickpath_copy.FCStd"))
    doc = FreeCAD.openDocument(os.path.join(out_dir, "clickpath_copy.FCStd"))
    FreeCADGui.updateGui()
    objs = [doc.getObject(n) for n in names]
    check(all(o is not None for o in objs) and [type(o.Proxy).__name__ for o in objs] ==
          ["CageProxy", "CageProxy", "SurfaceProxy"] and [type(o.ViewObject.Proxy).__name__ for o in objs] ==
          ["ViewProviderCage", "ViewProviderCage", "ViewProviderSurface"] and objs[2].Cage is objs[1]
          and len(objs[2].Shape.Faces) == objs[2].PatchCount,
          "saved and reopened in the GUI: proxies, view providers and shapes back")
    print("total %.1f s" % (time.time() - t0))


def check_icons(CageKitGui, mw):
    """One icon per command: distinct SVG files that Qt loads, shown on the toolbar's actions."""
    from PySide import QtCore, QtGui
    files = [CageKitGui.icon(getattr(CageKitGui, c.replace("CageKit_", "")).pixmap) for c in CageKitGui.COMMANDS]
    contents = [open(f, "rb").read() if os.path.isfile(f) else b"" for f in files]
    loaded = [not QtGui.QIcon(f).pixmap(32, 32).isNull() for f in files]
    check(len(set(files)) == len(files) == 5 and all(contents) and len(set(contents)) == len(contents) and all(loaded),
          "one icon per command, distinct SVG files that Qt renders: %s" % ", ".join(os.path.basename(f) for f in files))
    bars = [b for b in mw.findChildren(QtGui.QToolBar) if b.windowTitle().replace("&", "") == "CageKit"]
    actions = [a for b in bars for a in b.actions() if not a.isSeparator()]

    def image(a):
        buf = QtCore.QBuffer()
        buf.open(QtCore.QIODevice.WriteOnly)
        a.icon().pixmap(32, 32).toImage().save(buf, "PNG")
        return bytes(buf.data())
    images = [image(a) for a in actions if not a.icon().isNull()]
    check(len(actions) == 5 and len(images) == 5 and len(set(images)) == 5,
          "the CageKit toolbar shows %d distinct icons on its %d actions" % (len(set(images)), len(actions)))


def write_block(path):
    """A tessellated 2 x 1.4 x 0.8 box (8 x 8 grid per side) as OBJ."""
    n = 8
    size = (2.0, 1.4, 0.8)
    verts, index, faces = [], {}, []

    def vid(p):
        key = tuple(round(c, 9) for c in p)
        if key not in index:
            index[key] = len(verts)
            verts.append(key)
        return index[key]
    for axis in range(3):
        for side in (0.0, 1.0):
            u, v = [a for a in range(3) if a != axis]
            for i in range(n):
                for j in range(n):
                    quad = []
                    for di, dj in ((0, 0), (1, 0), (1, 1), (0, 1)):
                        p = [0.0, 0.0, 0.0]
                        p[axis], p[u], p[v] = side, (i + di) / n, (j + dj) / n
                        quad.append(vid([p[k] * size[k] for k in range(3)]))
                    if (side == 1.0) == (axis == 1):
                        quad.reverse()
                    faces += [(quad[0], quad[1], quad[2]), (quad[0], quad[2], quad[3])]
    with open(path, "w") as f:
        f.writelines("v %r %r %r\n" % p for p in verts)
        f.writelines("f %d %d %d\n" % tuple(i + 1 for i in t) for t in faces)


try:
    scratch = os.environ.get("CAGEKIT_TEST_OUT")
    if scratch:
        os.makedirs(scratch, exist_ok=True)
        main(scratch)
    else:
        with tempfile.TemporaryDirectory() as tmp:
            main(tmp)
except Exception:
    traceback.print_exc()
    failures.append("exception")
print("%d failure(s)" % len(failures), flush=True)
if failures:
    print("FAILED:\n  " + "\n  ".join(failures), flush=True)
sys.stdout.flush()
sys.stderr.flush()
os._exit(1 if failures else 0)
