# SPDX-License-Identifier: GPL-3.0-or-later
"""The workbench's parametric objects and undo in FreeCAD, headless (ctest freecad.parametric,
label freecad):

    freecadcmd bindings/freecad/tests/test_freecad_parametric.py

freecadcmd 0.20 passes no arguments to a script, so it reads the environment: CAGEKIT_LIBRARY (the
built libcagekit), CAGEKIT_TEST_OUT (scratch folder; default a temporary one). The scan is a
generated noisy block (no shared files), so the test takes seconds.
Checks, with the document's UndoMode on:
- undo and redo of every command's function (import_scan, scan_to_cage, fit_cage, limit_surface,
  export_step of a cage without a surface): the object appears / disappears / its control points
  revert, and comes back (with its Proxy) on redo;
- a recompute after a property change changes the result: the cage's Faces (it is rebuilt from the
  scan, with fewer faces; its surface follows), the surface's Tolerance (a length, mode patches:
  fewer patches at a larger tolerance) and Mode; undo of such a change reverts the result;
- a failed command leaves nothing (the transaction aborted), a progress callback returning False
  cancels a job (cagekit.CancelledError);
- save and reload of a document with the Part::FeaturePython objects (their proxies come back,
  the shapes are kept, a property change recomputes again);
- a plain Part::Feature cage (documents made before the parametric objects) still works.
Exit code 1 on any failure.
"""
import os
import sys
import tempfile
import time
import traceback

import FreeCAD

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", "..", ".."))

failures = []


def check(cond, what):
    print(("ok    " if cond else "FAIL  ") + what, flush=True)
    if not cond:
        failures.append(what)


def write_block(path, n=8):
    """A noisy tessellated 2 x 1.4 x 0.8 box (n x n grid per side, welded, outward) as OBJ."""
    import numpy as np
    t = np.linspace(0, 1, n + 1)
    verts, faces, index = [], [], {}

    def vid(p):
        key = tuple(np.round(p, 9))
        if key not in index:
            index[key] = len(verts)
            verts.append(p)
        return index[key]
    size = np.array([2.0, 1.4, 0.8])
    for axis in range(3):
        for side in (0.0, 1.0):
            u, v = [a for a in range(3) if a != axis]
            for i in range(n):
                for j in range(n):
                    quad = []
                    for di, dj in ((0, 0), (1, 0), (1, 1), (0, 1)):
                        p = np.zeros(3)
                        p[axis], p[u], p[v] = side, t[i + di], t[j + dj]
                        quad.append(vid(p * size))
                    if (side == 1.0) == (axis == 1):
                        quad.reverse()
                    faces += [[quad[0], quad[1], quad[2]], [quad[0], quad[2], quad[3]]]
    pos = np.array(verts) + np.random.default_rng(7).normal(scale=2e-3, size=(len(verts), 3))
    with open(path, "w") as f:
        f.writelines("v %r %r %r\n" % tuple(map(float, p)) for p in pos)
        f.writelines("f %d %d %d\n" % tuple(i + 1 for i in q) for q in faces)


def names(doc):
    return sorted(o.Name for o in doc.Objects)


def proxy_name(obj):
    return type(getattr(obj, "Proxy", None)).__name__


def ptex_faces(cage):
    return sum(1 if int(n) == 4 else int(n) for n in cage.FaceSizes)


def main(out_dir):
    t_start = time.time()
    sys.path[:0] = [os.path.join(ROOT, "bindings", "freecad", "CageKit"), os.path.join(ROOT, "bindings", "python")]
    import CageKitTools as tools
    cagekit = tools.sdk()
    print("FreeCAD %s, cagekit %s at %s" % (".".join(FreeCAD.Version()[:3]), cagekit.version(), cagekit.library_path))
    doc = FreeCAD.newDocument("CageKitParametric")
    doc.UndoMode = 1

    def undo_redo(what, before, after):
        """Undo: state() == before; redo: state() == after (state: a callable)."""
        doc.undo()
        undone = before()
        doc.redo()
        redone = after()
        check(undone and redone, "%s: undo reverts it, redo restores it" % what)

    # --- import scan ------------------------------------------------------------------------------
    path = os.path.join(out_dir, "block.obj")
    write_block(path)
    scan = tools.import_scan(path, doc)
    scan_name = scan.Name
    check(names(doc) == [scan_name] and scan.Mesh.CountFacets == 6 * 8 * 8 * 2 and doc.UndoCount == 1,
          "import_scan: one mesh object, one undo step (%s)" % doc.UndoNames)
    undo_redo("import_scan", lambda: names(doc) == [], lambda: names(doc) == [scan_name])
    scan = doc.getObject(scan_name)

    # --- scan to cage -----------------------------------------------------------------------------
    t = time.time()
    cage = tools.scan_to_cage(scan, faces=60)
    cage_name = cage.Name
    faces60 = len(cage.FaceSizes)
    check(proxy_name(cage) == "CageProxy" and cage.TypeId == "Part::FeaturePython" and cage.Faces == 60
          and cage.Scan is scan and faces60 > 0 and len(cage.Shape.Edges) > 0 and cage.InputKey
          and doc.UndoNames[0] == "CageKit: scan to cage",
          "scan_to_cage: a Part::FeaturePython cage (CageProxy), %d faces for 60 asked (%.1f s)"
          % (faces60, time.time() - t))
    undo_redo("scan_to_cage", lambda: cage_name not in names(doc),
              lambda: cage_name in names(doc) and proxy_name(doc.getObject(cage_name)) == "CageProxy"
              and len(doc.getObject(cage_name).FaceSizes) == faces60)
    cage = doc.getObject(cage_name)

    # --- fit ----------------------------------------------------------------------------------------
    before = [tuple(p) for p in cage.ControlPoints]
    report = tools.fit_cage(cage, passes=2)
    after = [tuple(p) for p in cage.ControlPoints]
    check(after != before and cage.FitAfter == 2 and cage.FitPasses >= 1
          and abs(cage.FitRmsRel - report.final.rms_rel) < 1e-15 and doc.UndoNames[0] == "CageKit: fit",
          "fit_cage: control points moved, FitAfter 2, rms %.2e" % cage.FitRmsRel)
    undo_redo("fit_cage", lambda: [tuple(p) for p in cage.ControlPoints] == before and cage.FitAfter == 0,
              lambda: [tuple(p) for p in cage.ControlPoints] == after and cage.FitAfter == 2)
    doc.recompute()
    check([tuple(p) for p in cage.ControlPoints] == after, "a recompute after the redo keeps the fit (no rebuild)")

    # --- limit surface ------------------------------------------------------------------------------
    diag = tools.bbox_diagonal(tools.cage_arrays(cage))
    t = time.time()
    surface = tools.limit_surface(cage, length=1e-3 * diag)
    surface_name = surface.Name
    ptex = ptex_faces(cage)
    check(proxy_name(surface) == "SurfaceProxy" and surface.Cage is cage and surface.Mode == "bspline"
          and abs(surface.Tolerance.Value - 1e-3 * diag) < 1e-15 * diag and abs(surface.ToleranceRel - 1e-3) < 1e-12
          and abs(surface.BBoxDiagonal - diag) < 1e-12 * diag and surface.PatchCount == ptex
          and surface.Closed and surface.Valid,
          "limit_surface(length=1e-3 x diagonal = %.4g mm): SurfaceProxy, Tolerance %s, the SDK's diagonal %.6g == "
          "the workbench's, %d faces, a valid solid (%.1f s)" % (1e-3 * diag, surface.Tolerance, surface.BBoxDiagonal,
                                                                 surface.PatchCount, time.time() - t))
    undo_redo("limit_surface", lambda: surface_name not in names(doc),
              lambda: surface_name in names(doc) and proxy_name(doc.getObject(surface_name)) == "SurfaceProxy"
              and doc.getObject(surface_name).PatchCount == ptex)
    surface = doc.getObject(surface_name)

    # --- recompute after property changes -----------------------------------------------------------
    t = time.time()
    with tools.transaction(doc, "faces 30"):
        cage.Faces = 30
        doc.recompute()
    faces30 = len(cage.FaceSizes)
    check(faces30 < faces60 and cage.LevelFaces <= cage.TargetFaces and cage.TargetFaces >= 30
          and cage.FitAfter == 2 and cage.FitPasses >= 1,
          "cage.Faces 60 -> 30 + recompute: rebuilt from the scan, %d -> %d faces (level %d, target %d), fitted "
          "again (%.1f s)" % (faces60, faces30, cage.LevelFaces, cage.TargetFaces, time.time() - t))
    check(surface.PatchCount == ptex_faces(cage) < ptex and surface.Valid and surface.Closed
          and surface.InputKey == tools.surface_input_key(surface),
          "the surface followed its cage: %d -> %d faces" % (ptex, surface.PatchCount))
    undo_redo("the Faces change", lambda: cage.Faces == 60 and len(cage.FaceSizes) == faces60
              and surface.PatchCount == ptex,
              lambda: cage.Faces == 30 and len(cage.FaceSizes) == faces30 and surface.PatchCount == ptex_faces(cage))
    doc.recompute()
    check(len(cage.FaceSizes) == faces30, "a recompute after the redo rebuilds nothing")
    diag = tools.bbox_diagonal(tools.cage_arrays(cage))  # of the rebuilt cage
    with tools.transaction(doc, "patches"):
        surface.Mode = "patches"
        surface.Tolerance = 1e-3 * diag
        doc.recompute()
    fine = surface.PatchCount
    fine_error = surface.MaxErrorRel
    with tools.transaction(doc, "tolerance"):
        surface.Tolerance = FreeCAD.Units.Quantity(2e-2 * diag, FreeCAD.Units.Length)
        doc.recompute()
    coarse = surface.PatchCount
    check(fine > coarse > 0 and surface.Mode == "patches" and abs(surface.ToleranceRel - 2e-2) < 1e-9
          and surface.MaxErrorRel <= 2e-2 + 1e-12 and surface.Valid and len(surface.Shape.Faces) == coarse,
          "surface.Tolerance 1e-3 -> 2e-2 of the diagonal (mode patches) + recompute: %d -> %d patches, max error "
          "%.1e -> %.1e (ToleranceRel %.3g, valid %s)" % (fine, coarse, fine_error, surface.MaxErrorRel,
                                                         surface.ToleranceRel, surface.Valid))
    undo_redo("the Tolerance change", lambda: surface.PatchCount == fine and len(surface.Shape.Faces) == fine,
              lambda: surface.PatchCount == coarse and len(surface.Shape.Faces) == coarse)

    # --- failures and cancel ---------------------------------------------------------------------------
    count, steps = len(doc.Objects), doc.UndoCount
    messages = []
    out = tools.run_reported(tools.limit_surface, cage, length=0.0, report=messages.append)
    check(out is None and messages and "tolerance" in messages[0] and len(doc.Objects) == count
          and doc.UndoCount == steps and surface.PatchCount == coarse,
          "limit_surface(length=0) -> %r, nothing changed, no undo step" % (messages[0] if messages else None))
    try:
        with tools.transaction(doc, "fails"):
            doc.addObject("Part::Feature", "Doomed")
            raise tools.WorkbenchError("on purpose")
    except tools.WorkbenchError:
        pass
    check(len(doc.Objects) == count and doc.getObject("Doomed") is None and doc.UndoCount == steps,
          "an exception inside a transaction aborts it (the object added is gone)")
    stages = []

    def cancel(stage, fraction):
        stages.append(stage)
        return False
    pos, tris = tools.mesh_arrays(scan)
    try:
        tools.cage_job(pos, tris, faces=60, progress=cancel)
        cancelled = False
    except cagekit.CancelledError:
        cancelled = True
    check(cancelled and len(stages) >= 1 and len(doc.Objects) == count,
          "a job whose progress callback returns False raises CancelledError at its first callback (%r)"
          % (stages[:1],))

    # --- export STEP of a cage without a surface ----------------------------------------------------------
    other = tools.scan_to_cage(scan, faces=30)
    step = os.path.join(out_dir, "other.step")
    n = len(doc.Objects)
    tools.export_step(other, step)
    made = tools.surface_of(other)
    check(os.path.getsize(step) > 0 and made is not None and len(doc.Objects) == n + 1,
          "export_step(cage without a surface): %r made, STEP written" % (made.Label if made else None))
    made_name = made.Name
    undo_redo("export_step's surface", lambda: made_name not in names(doc) and len(doc.Objects) == n,
              lambda: made_name in names(doc))

    # --- save and reload ------------------------------------------------------------------------------
    fcstd = os.path.join(out_dir, "parametric.FCStd")
    doc.saveAs(fcstd)
    faces_saved, patches_saved = len(cage.FaceSizes), surface.PatchCount
    FreeCAD.closeDocument(doc.Name)
    doc = FreeCAD.openDocument(fcstd)
    doc.UndoMode = 1
    cage, surface = doc.getObject(cage_name), doc.getObject(surface_name)
    check(proxy_name(cage) == "CageProxy" and proxy_name(surface) == "SurfaceProxy" and cage.Scan is not None
          and surface.Cage is cage and len(cage.FaceSizes) == faces_saved and surface.PatchCount == patches_saved
          and len(surface.Shape.Faces) == patches_saved and surface.Shape.ShapeType == "Solid"
          and len(cage.Shape.Edges) > 0,
          "saved and reloaded: proxies back, %d cage faces, %d surface faces" % (faces_saved, patches_saved))
    doc.recompute()
    check(surface.PatchCount == patches_saved and len(cage.FaceSizes) == faces_saved,
          "a recompute after the reload computes nothing new (InputKey kept)")
    cage.Faces = 60
    surface.Tolerance = 1e-3 * diag
    doc.recompute()
    check(len(cage.FaceSizes) == faces60 and surface.PatchCount > patches_saved and surface.Valid,
          "after the reload, Faces 60 and Tolerance 1e-3 recompute: %d cage faces, %d patches"
          % (len(cage.FaceSizes), surface.PatchCount))

    # --- a plain Part::Feature cage (documents from before the parametric objects) --------------------------
    legacy = doc.addObject("Part::Feature", "OldCage")
    for name, kind, text in tools._CAGE_PROPERTIES:
        if name not in tools._CAGE_INPUTS[1:] and name != "InputKey":
            legacy.addProperty(kind, name, "CageKit", text)
    tools.write_cage(legacy, tools.cage_arrays(cage))
    legacy.Scan = cage.Scan
    tools.fit_cage(legacy, passes=1)
    old_surface = tools.limit_surface(legacy, tolerance=1e-3)
    check(tools.is_cage(legacy) and legacy.FitPasses >= 1 and proxy_name(old_surface) == "SurfaceProxy"
          and old_surface.Cage is legacy and old_surface.Valid,
          "a plain Part::Feature cage: fit_cage and limit_surface work (a parametric surface, %d faces)"
          % old_surface.PatchCount)
    FreeCAD.closeDocument(doc.Name)
    print("total %.1f s" % (time.time() - t_start))


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
    sys.exit(1)
sys.exit(0)
