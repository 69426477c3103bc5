# SPDX-License-Identifier: GPL-3.0-or-later
"""CageKit in FreeCAD, without the GUI: scan mesh -> cage -> fit -> limit surface -> STEP.

The workbench's commands (CageKitGui) only add dialogs and worker threads around these
functions, and they work the same in `freecadcmd`:

    import FreeCAD, CageKitTools as ck
    doc = FreeCAD.newDocument()
    doc.UndoMode = 1                                       # freecadcmd: record undo steps
    scan = ck.import_scan("fandisk.obj", doc)              # or any Mesh::Feature
    cage = ck.scan_to_cage(scan, faces=200)                # parametric cage "<scan>_cage"
    ck.fit_cage(cage, passes=5)                            # moves its control points
    surface = ck.limit_surface(cage, length=0.01)          # parametric "<cage>_surface", tolerance 0.01 mm
    ck.export_step(surface, "fandisk.step")
    cage.Faces = 100; doc.recompute()                      # the cage is rebuilt, its surface follows
    doc.undo()                                             # every function above is one undo step

Without a document (a cagekit.Cage or a cage object; the dict also holds the faces, the SDK's
record, the sewing tolerance and timings):

    result = ck.surface_shape(cage, tolerance=1e-3, step="out.step")   # mode="bspline" | "patches"
    result["shape"], result["closed"], result["valid"], result["seconds"]
    ck.step_round_trip("out.step", result)                 # face count, solid, limit points' distances

Objects: a cage is a Part::FeaturePython (CageProxy) whose Shape is the cage's edges and whose
properties (group "CageKit") hold its inputs (Scan, Faces, CreaseAngle, Passes, KeepCreaseVertices,
FitAfter), the control mesh and its tags (ControlPoints, FaceSizes, FaceIndices, Creases,
CreaseSharpness, Corners, CornerSharpness, Holes, BoundaryRule) and the journey's figures. The limit
surface is a Part::FeaturePython (SurfaceProxy) with inputs Cage, Mode, Tolerance (a length in
document units; the SDK gets Tolerance / the bounding-box diagonal of the control points, recorded
as ToleranceRel), MaxLevel, MaxDepth; its Shape has, in mode "bspline" (the default), one B-spline
face per merged surface of cagekit_limit_surfaces_create (bicubic with interior knots, one per ptex
face), or, in mode "patches", one face per patch of cagekit_limit_patches_create (bicubic, knots
[0, 1] with multiplicity 4: a Bezier patch); sewn into a shell, a solid when the shell is closed.
Both recompute (execute()) when their inputs differ from those of their last computation (a digest
in the hidden property InputKey), so an undo, a reload or a recompute without a change costs nothing.
Plain Part::Feature cages and surfaces of older documents are still read (is_cage, fit_cage,
limit_surface, export_step); they do not recompute. Coordinates are global: a scan's Placement is
applied, the objects made have the identity Placement.

Undo: each function that changes a document does it inside transaction(doc, name) (one undo step;
an exception aborts it, so nothing is left behind). Jobs: the SDK work of each step is a function on
plain arrays (read_scan_job, cage_job, fit_job, surface_sdk + surface_faces, surface_solid) that
touches no document, so the GUI runs it on a worker thread (the SDK releases the GIL); its
`progress(stage, fraction)` callback returning False cancels it (cagekit.CancelledError). The
document steps (add_scan, add_cage, apply_fit, apply_surface) run on the main thread.

Errors: every function raises a cagekit.CageKitError (the SDK's message), WorkbenchError (input
this module refuses before calling the SDK) or ImportError (the library cannot be loaded).
run_reported() turns them into a FreeCAD console error and a message for the host; nothing here
lets an exception reach FreeCAD's core.
"""
import contextlib
import math
import os
import tempfile
import time

import FreeCAD
import Part

GROUP = "CageKit"


class WorkbenchError(Exception):
    """Input refused by the workbench itself (not a mesh, no faces, not a cage, ...)."""


# --- the SDK ---------------------------------------------------------------------------------------
_cagekit = None


def sdk():
    """The `cagekit` package: the copy bundled in this addon folder (CageKit/cagekit, with
    libcagekit.so.2 next to it: the freecad_addon target), else the one on sys.path: the cagekit
    wheel pip-installed into FreeCAD's AdditionalPythonPackages folder (this repository installed
    by the Addon Manager; bindings/freecad/README.md), or bindings/python in a source tree with
    CAGEKIT_LIBRARY naming the library. ImportError carries the package's message."""
    global _cagekit
    if _cagekit is None:
        import cagekit
        _cagekit = cagekit
    return _cagekit


def numpy():
    import numpy as np
    return np


def message_of(error):
    """The text shown to the user for an exception raised by this module."""
    text = (getattr(error, "message", None) or str(error) or type(error).__name__).strip()
    return text if text.startswith("CageKit") else "CageKit: " + text


def run_reported(action, *args, report=None, **kwargs):
    """action(*args, **kwargs); on an exception prints it to FreeCAD's report view, calls
    report(text) (the GUI shows a message box) and returns None. Also catches ImportError (no
    library) and any other Exception, so that none reaches FreeCAD's core."""
    try:
        return action(*args, **kwargs)
    except Exception as e:  # SDK errors, missing library, bad input
        text = message_of(e)
        FreeCAD.Console.PrintError(text + "\n")
        if report is not None:
            try:
                report(text)
            except Exception:
                pass
        return None


class Progress:
    """CageKit's progress callback -> FreeCAD's progress indicator (the status bar's in the GUI,
    percentages on the console in freecadcmd); Esc in the GUI cancels the SDK call."""

    def __init__(self, text, steps=100):
        self.last = -1
        self.indicator = None
        try:
            self.indicator = FreeCAD.Base.ProgressIndicator()
            self.indicator.start(text, steps)
        except Exception:
            self.indicator = None

    def __call__(self, stage, fraction):
        if self.indicator is None:
            return None
        step = int(100 * min(max(float(fraction), 0.0), 1.0))
        try:
            while self.last < step:
                self.last += 1
                self.indicator.next(True)
        except Exception:  # the user aborted the indicator: cancel the SDK call
            return False
        return None

    def stop(self):
        if self.indicator is not None:
            try:
                self.indicator.stop()
            except Exception:
                pass
            self.indicator = None


# --- reading FreeCAD objects -------------------------------------------------------------------------
def mesh_arrays(obj):
    """(positions (N, 3) float64, global coordinates; triangles (F, 3) uint32) of a mesh object."""
    np = numpy()
    mesh = getattr(obj, "Mesh", None)
    if mesh is None or not hasattr(mesh, "Topology"):
        raise WorkbenchError("%r is not a mesh object" % getattr(obj, "Label", obj))
    points, facets = mesh.Topology  # the object's Placement applied
    if len(facets) == 0:
        raise WorkbenchError("mesh %r has no faces" % obj.Label)
    pos = np.array([(p.x, p.y, p.z) for p in points], dtype=np.float64).reshape(-1, 3)
    tris = np.array(facets, dtype=np.int64).reshape(-1, 3)
    return pos, tris.astype(np.uint32)


def is_cage(obj):
    return obj is not None and "ControlPoints" in getattr(obj, "PropertiesList", ()) \
        and "FaceSizes" in obj.PropertiesList


def is_limit_surface(obj):
    return obj is not None and "PatchCount" in getattr(obj, "PropertiesList", ()) \
        and hasattr(obj, "Shape")


def cage_arrays(obj):
    """dict of the cage object's control mesh and tags (numpy arrays)."""
    np = numpy()
    if not is_cage(obj):
        raise WorkbenchError("%r is not a CageKit cage" % getattr(obj, "Label", obj))
    sizes = np.array(obj.FaceSizes, dtype=np.int64)
    flat = np.array(obj.FaceIndices, dtype=np.int64)
    pos = np.array([(p.x, p.y, p.z) for p in obj.ControlPoints], dtype=np.float64).reshape(-1, 3)
    if len(sizes) == 0 or sizes.sum() != len(flat):
        raise WorkbenchError("cage %r: %d face sizes do not match %d face indices"
                             % (obj.Label, len(sizes), len(flat)))
    creases = np.array(obj.Creases, dtype=np.int64)
    if creases.size % 2 or len(obj.CreaseSharpness) != creases.size // 2:
        raise WorkbenchError("cage %r: Creases must be vertex pairs, one sharpness each" % obj.Label)
    if len(obj.CornerSharpness) != len(obj.Corners):
        raise WorkbenchError("cage %r: one sharpness per corner" % obj.Label)
    return {"positions": pos, "sizes": sizes, "flat": flat, "creases": creases.reshape(-1, 2),
            "crease_sharpness": np.array(obj.CreaseSharpness, dtype=np.float64),
            "corners": np.array(obj.Corners, dtype=np.int64),
            "corner_sharpness": np.array(obj.CornerSharpness, dtype=np.float64),
            "holes": np.array(obj.Holes, dtype=np.int64), "boundary_rule": int(obj.BoundaryRule)}


def cage_from_object(obj, context=None):
    """A cagekit.Cage of a cage object (the SDK validates it: InvalidMeshError names a problem)."""
    return cage_from_arrays(cage_arrays(obj), context)


def cage_from_arrays(a, context=None):
    """A cagekit.Cage of cage_arrays()' dict (no FreeCAD object: usable on a worker thread)."""
    ck = sdk()
    return ck.Cage.from_arrays(a["positions"], (a["sizes"], a["flat"]), creases=a["creases"],
                               crease_sharpness=a["crease_sharpness"], corners=a["corners"],
                               corner_sharpness=a["corner_sharpness"], holes=a["holes"],
                               boundary_rule=a["boundary_rule"], context=context)


def cage_data(cage):
    """dict of a cagekit.Cage's arrays, as cage_arrays() returns them."""
    np = numpy()
    sizes, flat = cage.face_arrays()
    pairs, sharp = cage.creases
    corners, corner_sharp = cage.corners
    return {"positions": cage.positions, "sizes": sizes.astype(np.int64), "flat": flat.astype(np.int64),
            "creases": pairs.astype(np.int64), "crease_sharpness": sharp.astype(np.float64),
            "corners": corners.astype(np.int64), "corner_sharpness": corner_sharp.astype(np.float64),
            "holes": cage.holes.astype(np.int64), "boundary_rule": int(cage.boundary_rule)}


# --- undo transactions -------------------------------------------------------------------------------
_open_transactions = {}


@contextlib.contextmanager
def transaction(doc, name):
    """Every change to `doc` inside the block is one undo step named `name` (doc.openTransaction /
    commitTransaction); an exception aborts it (abortTransaction: the changes are rolled back) and
    is raised again. Nested blocks on the same document join the outer one. FreeCAD records undo
    steps only while the document's UndoMode is on (the GUI's default; doc.UndoMode = 1 in
    freecadcmd): otherwise the block just runs."""
    key = doc.Name
    outer = _open_transactions.get(key, 0) == 0
    if outer:
        doc.openTransaction(name)
    _open_transactions[key] = _open_transactions.get(key, 0) + 1
    try:
        yield
    except BaseException:
        _open_transactions[key] -= 1
        if outer:
            doc.abortTransaction()
        raise
    _open_transactions[key] -= 1
    if outer:
        doc.commitTransaction()


# --- making FreeCAD objects ----------------------------------------------------------------------------
def _property(obj, kind, name, doc, read_only=False, hidden=False):
    if name not in obj.PropertiesList:
        obj.addProperty(kind, name, GROUP, doc)
    if hidden:
        obj.setEditorMode(name, 2)
    elif read_only:
        obj.setEditorMode(name, 1)


def _vectors(points):
    V = FreeCAD.Vector
    return [V(float(p[0]), float(p[1]), float(p[2])) for p in points]


def _digest(*items):
    """A short hex digest of numpy arrays and plain values (the inputs a parametric object was
    last computed from)."""
    import hashlib
    np = numpy()
    h = hashlib.sha1()
    for item in items:
        if isinstance(item, np.ndarray):
            h.update(str((item.dtype.str, item.shape)).encode())
            h.update(np.ascontiguousarray(item).tobytes())
        else:
            h.update(repr(item).encode())
        h.update(b"|")
    return h.hexdigest()


def scan_fingerprint(scan):
    """A cheap fingerprint of a mesh object's geometry (counts, bounding box, area, volume and
    Placement, all computed by FreeCAD): what a cage's rebuild depends on."""
    if scan is None:
        return None
    mesh = scan.Mesh
    box = mesh.BoundBox
    return (scan.Name, mesh.CountPoints, mesh.CountFacets, box.XMin, box.YMin, box.ZMin, box.XMax, box.YMax,
            box.ZMax, float(mesh.Area), float(mesh.Volume), tuple(scan.Placement.toMatrix().A))


def cage_edges_shape(positions, sizes, flat):
    """A compound of the cage's edges (each once; zero-length ones left out)."""
    V = FreeCAD.Vector
    seen, edges, at = set(), [], 0
    for n in sizes:
        n = int(n)
        loop = [int(i) for i in flat[at:at + n]]
        at += n
        for a, b in zip(loop, loop[1:] + loop[:1]):
            key = (a, b) if a < b else (b, a)
            if key in seen:
                continue
            seen.add(key)
            p, q = V(*map(float, positions[a])), V(*map(float, positions[b]))
            if (p - q).Length > 0.0:
                edges.append(Part.LineSegment(p, q).toShape())
    return Part.makeCompound(edges)


def write_cage(obj, data):
    """Stores `data` (cage_data()) in the cage object's properties and rebuilds its Shape."""
    obj.ControlPoints = _vectors(data["positions"])
    obj.FaceSizes = [int(x) for x in data["sizes"]]
    obj.FaceIndices = [int(x) for x in data["flat"]]
    obj.Creases = [int(x) for x in data["creases"].reshape(-1)]
    obj.CreaseSharpness = [float(x) for x in data["crease_sharpness"]]
    obj.Corners = [int(x) for x in data["corners"]]
    obj.CornerSharpness = [float(x) for x in data["corner_sharpness"]]
    obj.Holes = [int(x) for x in data["holes"]]
    obj.BoundaryRule = int(data["boundary_rule"])
    obj.Shape = cage_edges_shape(data["positions"], data["sizes"], data["flat"])


_CAGE_PROPERTIES = (
    ("Scan", "App::PropertyLink", "The scanned mesh this cage is made from / fitted to (a change rebuilds the cage)"),
    ("Faces", "App::PropertyInteger", "Asked face count of the simplified level (a change rebuilds the cage)"),
    ("CreaseAngle", "App::PropertyAngle", "Cage edges with a dihedral angle beyond this become creases (rebuilds)"),
    ("Passes", "App::PropertyInteger", "Fitting passes of the journey from the scan (rebuilds)"),
    ("KeepCreaseVertices", "App::PropertyBool", "Fits do not move crease vertices (rebuilds)"),
    ("FitAfter", "App::PropertyInteger", "Passes of the Fit command done since the cage was made (a rebuild from the "
                                         "scan fits this many passes after the journey)"),
    ("ControlPoints", "App::PropertyVectorList", "Control points of the Catmull-Clark cage"),
    ("FaceSizes", "App::PropertyIntegerList", "Vertex count of each cage face"),
    ("FaceIndices", "App::PropertyIntegerList", "Control point indices of the faces, face after face"),
    ("Creases", "App::PropertyIntegerList", "Crease edges as control point index pairs, flattened"),
    ("CreaseSharpness", "App::PropertyFloatList", "Sharpness per crease (10: infinitely sharp)"),
    ("Corners", "App::PropertyIntegerList", "Corner (sharp) control points"),
    ("CornerSharpness", "App::PropertyFloatList", "Sharpness per corner"),
    ("Holes", "App::PropertyIntegerList", "Hole faces (not part of the limit surface)"),
    ("BoundaryRule", "App::PropertyInteger", "0: boundary edges sharp; 1: boundary corners pinned too"),
    ("LevelFaces", "App::PropertyInteger", "Faces of the simplification level"),
    ("TargetFaces", "App::PropertyInteger",
     "Face target the journey used (raised from the request while the limit strays or self-intersects)"),
    ("FitPasses", "App::PropertyInteger", "Fitting passes done (0: not fitted)"),
    ("FitRmsRel", "App::PropertyFloat", "RMS distance scan -> limit surface / bbox diagonal"),
    ("InputKey", "App::PropertyString", "Digest of the inputs the cage was last built from"))
_CAGE_INPUTS = ("Scan", "Faces", "CreaseAngle", "Passes", "KeepCreaseVertices", "FitAfter")
_CAGE_READ_ONLY = ("LevelFaces", "TargetFaces", "FitPasses", "FitRmsRel")


def _add_cage_properties(obj):
    for name, kind, text in _CAGE_PROPERTIES:
        _property(obj, kind, name, text, read_only=name in _CAGE_READ_ONLY, hidden=name == "InputKey")


def cage_input_key(obj):
    """The digest of what a rebuild of the cage object from its scan depends on ("" without a
    scan: the control mesh is then the cage's own data)."""
    scan = getattr(obj, "Scan", None)
    if scan is None:
        return ""
    return _digest(scan_fingerprint(scan), int(obj.Faces), float(obj.CreaseAngle), int(obj.Passes),
                   bool(obj.KeepCreaseVertices), int(obj.FitAfter))


# Set by CageKitGui when the GUI is up: background_recompute(obj, kind) starts the computation of a
# CageKit object's new result ("cage" or "surface") on a worker thread and returns True (the
# result is written when it arrives, as one undo step "CageKit: recompute"), or returns False
# (a job is running already): execute() then computes synchronously, as it always does without it.
background_recompute = None


def _in_background(obj, kind):
    try:
        return background_recompute is not None and bool(background_recompute(obj, kind))
    except Exception as e:  # compute synchronously instead
        FreeCAD.Console.PrintWarning("CageKit: no background recompute of %r: %s\n" % (obj.Label, e))
        return False


def _has_proxy(obj, cls):
    return type(getattr(obj, "Proxy", None)).__name__ == cls.__name__


class CageProxy:
    """The Proxy of a parametric cage (Part::FeaturePython, properties in group CageKit).

    execute(): when its inputs (the linked Scan's geometry, Faces, CreaseAngle, Passes,
    KeepCreaseVertices, FitAfter) differ from those of the last build (InputKey), the cage is
    rebuilt from the scan (cage_job: the SDK's journey, then FitAfter fitting passes); otherwise
    (the control points edited, a Fit, an undo) only its Shape is remade from the control mesh.
    A cage without a Scan keeps its control mesh. Serialisable: no state besides the object's
    properties."""

    Type = "CageKitCage"

    def __init__(self, obj):
        obj.Proxy = self
        _add_cage_properties(obj)

    def onDocumentRestored(self, obj):
        _add_cage_properties(obj)

    def execute(self, obj):
        key = cage_input_key(obj)
        if key and key != obj.InputKey:
            if _in_background(obj, "cage"):
                return  # the Shape stays until the job's result arrives
            FreeCAD.Console.PrintMessage("CageKit: rebuilding %r from %r\n" % (obj.Label, obj.Scan.Label))
            pos, tris = mesh_arrays(obj.Scan)
            apply_cage(obj, cage_job(pos, tris, **cage_options(obj)))
        else:
            a = cage_arrays(obj)
            obj.Shape = cage_edges_shape(a["positions"], a["sizes"], a["flat"])

    def __getstate__(self):
        return None

    def __setstate__(self, state):
        return None


def new_cage_object(doc, label, data, scan=None, faces=0, crease_angle=30.0, passes=0, keep_crease_vertices=False):
    """A parametric cage object (Part::FeaturePython with a CageProxy) holding `data`
    (cage_data()); its inputs are set but not built from (its InputKey matches them)."""
    obj = doc.addObject("Part::FeaturePython", "Cage")
    CageProxy(obj)
    if FreeCAD.GuiUp:
        _attach_view_provider(obj, "cage")
    obj.Label = label
    obj.Scan = scan
    obj.Faces = int(faces)
    obj.CreaseAngle = float(crease_angle)
    obj.Passes = int(passes)
    obj.KeepCreaseVertices = bool(keep_crease_vertices)
    write_cage(obj, data)
    obj.InputKey = cage_input_key(obj)
    return obj


def _attach_view_provider(obj, kind):
    try:
        import CageKitGui
        CageKitGui.attach_view_provider(obj, kind)
    except Exception as e:  # the object works without its icon
        FreeCAD.Console.PrintWarning("CageKit: no view provider for %r: %s\n" % (obj.Label, e))


# --- the pipeline -----------------------------------------------------------------------------------------
# Each step is a job (SDK work on plain arrays: safe on a worker thread, the SDK releases the GIL;
# progress(stage, fraction) returning False cancels it: cagekit.CancelledError) and an apply step
# (the document changes, on FreeCAD's main thread, inside one undo transaction). The functions
# below run both synchronously; the GUI runs the jobs on a worker thread.
def read_scan_job(path, progress=None):
    """(name, positions (N, 3), triangles (F, 3)) of a mesh file read with the SDK (polygons split
    into triangle fans)."""
    np = numpy()
    ck = sdk()
    ctx = ck.Context(progress=progress)
    with ck.Mesh.read(path, context=ctx) as m:
        pos = m.positions
        sizes, flat = m.face_arrays()
    if len(sizes) == 0:
        raise WorkbenchError("%s has no faces" % path)
    tris, at = [], 0
    for n in sizes.tolist():
        loop = flat[at:at + n].tolist()
        at += n
        tris.extend((loop[0], loop[k], loop[k + 1]) for k in range(1, n - 1))
    name = os.path.splitext(os.path.basename(path))[0] or "Scan"
    return name, np.asarray(pos, dtype=np.float64), np.array(tris, dtype=np.int64).reshape(-1, 3)


def add_scan(doc, name, pos, tris):
    """A new Mesh::Feature `name` (one undo step)."""
    import Mesh
    mesh = Mesh.Mesh((_vectors(pos), [tuple(int(i) for i in t) for t in tris]))
    with transaction(doc, "CageKit: import scan"):
        obj = doc.addObject("Mesh::Feature", "Scan")
        obj.Label = name
        obj.Mesh = mesh
        doc.recompute()
    return obj


def import_scan(path, doc=None, context=None):
    """Reads a scan with the SDK (OBJ, PLY, OFF, Draco, STL; a bad file raises the SDK's ParseError
    etc. naming the file and line) into a new Mesh::Feature (polygons split into triangle fans).
    One undo step."""
    doc = doc or FreeCAD.ActiveDocument or FreeCAD.newDocument()
    return add_scan(doc, *read_scan_job(path))


def cage_options(obj):
    """The keyword arguments of cage_job from a parametric cage's inputs."""
    return {"faces": int(obj.Faces), "crease_angle": float(obj.CreaseAngle), "passes": int(obj.Passes),
            "keep_crease_vertices": bool(obj.KeepCreaseVertices), "fit_after": int(obj.FitAfter)}


def cage_job(pos, tris, faces=200, crease_angle=30.0, passes=0, keep_crease_vertices=False, fit_after=0,
             progress=None):
    """The SDK's journey (conditioning -> simplification to the finest level with at most `faces`
    faces -> the quad-dominant cage with creases beyond `crease_angle` degrees -> `passes` fitting
    passes -> a judged result: QualityError instead of a bad surface), then `fit_after` more
    fitting passes. Returns a dict: options, data (cage_data()), level_faces, target_faces,
    fit_passes, fit_rms_rel (None when not fitted), cage_quads."""
    ck = sdk()
    if int(faces) < 1:
        raise WorkbenchError("faces must be at least 1, not %r" % faces)
    options = {"faces": int(faces), "crease_angle": float(crease_angle), "passes": int(passes),
               "keep_crease_vertices": bool(keep_crease_vertices), "fit_after": int(fit_after)}
    ctx = ck.Context(progress=progress)
    fit_passes, rms = 0, None
    with ck.Mesh.from_arrays(pos, tris, context=ctx) as mesh:
        cage, limit, report = ck.scan_to_cage(mesh, faces=int(faces), crease_angle_degrees=float(crease_angle),
                                              fit={"max_passes": int(passes),
                                                   "keep_crease_vertices": bool(keep_crease_vertices)})
        limit.close()
        if int(passes) > 0:
            fit_passes, rms = report.fit_pass_count - 1, float(report.fit_final.rms_rel)
        with cage:
            if int(fit_after) > 0:
                fitted, fit_report = ck.fit(cage, mesh, max_passes=int(fit_after),
                                            keep_crease_vertices=bool(keep_crease_vertices))
                with fitted:
                    data = cage_data(fitted)
                fit_passes += len(fit_report.passes) - 1
                rms = float(fit_report.final.rms_rel)
            else:
                data = cage_data(cage)
    return {"options": options, "data": data, "level_faces": int(report.level_faces),
            "target_faces": int(report.simplify_target_used), "fit_passes": fit_passes, "fit_rms_rel": rms,
            "cage_quads": int(report.cage_quads)}


def apply_cage(obj, result):
    """Writes cage_job's result into the cage object (its data and figures; InputKey)."""
    write_cage(obj, result["data"])
    obj.LevelFaces = result["level_faces"]
    obj.TargetFaces = result["target_faces"]
    obj.FitPasses = result["fit_passes"]
    obj.FitRmsRel = result["fit_rms_rel"] or 0.0
    if "InputKey" in obj.PropertiesList:
        obj.InputKey = cage_input_key(obj)


def add_cage(scan, result, doc=None):
    """A new parametric cage '<scan>_cage' of cage_job's result (one undo step)."""
    doc = doc or scan.Document
    o = result["options"]
    data = result["data"]
    with transaction(doc, "CageKit: scan to cage"):
        obj = new_cage_object(doc, scan.Label + "_cage", data, scan, o["faces"], o["crease_angle"], o["passes"],
                              o["keep_crease_vertices"])
        obj.FitAfter = o["fit_after"]
        apply_cage(obj, result)
        doc.recompute()
    FreeCAD.Console.PrintMessage("CageKit: cage %r: %d faces (%d quads), %d creases%s\n" % (
        obj.Label, len(data["sizes"]), result["cage_quads"], len(data["creases"]),
        "" if result["fit_rms_rel"] is None else ", fitted (rms %.2g of the diagonal)" % result["fit_rms_rel"]))
    return obj


def scan_to_cage(scan, faces=200, crease_angle=30.0, passes=0, keep_crease_vertices=False, progress=None,
                 doc=None):
    """Simplifies the mesh object `scan` to the finest level with at most `faces` faces, builds the
    quad-dominant cage with creases beyond `crease_angle` degrees, optionally fits it in `passes`
    passes, and returns the new parametric cage object '<scan>_cage' (CageProxy: it rebuilds when
    the scan or these options change). One undo step; nothing is added on an error."""
    pos, tris = mesh_arrays(scan)
    result = cage_job(pos, tris, faces, crease_angle, passes, keep_crease_vertices, progress=progress)
    return add_cage(scan, result, doc)


def fit_job(scan_pos, scan_tris, cage, passes=5, keep_crease_vertices=False, progress=None):
    """Fits `cage` (cage_arrays()) to the scan's arrays in `passes` passes. Returns (data
    (cage_data()), the SDK's fit report)."""
    ck = sdk()
    if int(passes) < 1:
        raise WorkbenchError("passes must be at least 1, not %r" % passes)
    ctx = ck.Context(progress=progress)
    with ck.Mesh.from_arrays(scan_pos, scan_tris, context=ctx) as mesh, cage_from_arrays(cage, ctx) as c:
        fitted, report = ck.fit(c, mesh, max_passes=int(passes), keep_crease_vertices=bool(keep_crease_vertices))
        with fitted:
            data = cage_data(fitted)
    return data, report


def apply_fit(cage_obj, scan, data, report, passes, surfaces=()):
    """Writes fit_job's result into the cage object (one undo step). surfaces: (surface object,
    surface_shape's result for the fitted cage) pairs written in the same step, before the
    recompute (which then has nothing left to compute for them)."""
    with transaction(cage_obj.Document, "CageKit: fit"):
        write_cage(cage_obj, data)
        cage_obj.Scan = scan
        cage_obj.FitPasses = int(cage_obj.FitPasses) + len(report.passes) - 1
        cage_obj.FitRmsRel = float(report.final.rms_rel)
        if "FitAfter" in cage_obj.PropertiesList:
            cage_obj.FitAfter = int(cage_obj.FitAfter) + int(passes)
            cage_obj.InputKey = cage_input_key(cage_obj)
        for surface, result in surfaces:
            write_surface(surface, result, None)
        cage_obj.Document.recompute()
    FreeCAD.Console.PrintMessage("CageKit: %r fitted in %d passes: rms %.3g -> %.3g of the diagonal\n" % (
        cage_obj.Label, len(report.passes) - 1, report.initial.rms_rel, report.final.rms_rel))


def fit_cage(cage_obj, scan=None, passes=5, keep_crease_vertices=False, progress=None):
    """Fits the cage object's limit surface to `scan` (default: its Scan link) and stores the
    fitted control points in it (one undo step; a parametric cage adds `passes` to FitAfter).
    Returns the SDK's fit report."""
    scan = scan if scan is not None else getattr(cage_obj, "Scan", None)
    if scan is None:
        raise WorkbenchError("cage %r has no scan: select the scan too" % cage_obj.Label)
    pos, tris = mesh_arrays(scan)
    data, report = fit_job(pos, tris, cage_arrays(cage_obj), passes, keep_crease_vertices, progress)
    apply_fit(cage_obj, scan, data, report, passes)
    return report


def _sides(control_points):
    """(N, 4, 4, 3): the cubic Bezier boundary curves of each patch, side by side counter-clockwise
    in (s, t): 0 (t = 0, s 0 -> 1), 1 (s = 1, t 0 -> 1), 2 (t = 1, s 1 -> 0), 3 (s = 0, t 1 -> 0)."""
    np = numpy()
    cp = control_points
    return np.stack([cp[:, :, 0], cp[:, 3, :], cp[:, ::-1, 3], cp[:, 0, ::-1]], axis=1)


def _cubic(curves, t):
    """Points (K, 3) of K cubic Bezier curves (K, 4, 3) at t (K,)."""
    y = 1.0 - t
    w = [y ** 3, 3.0 * t * y * y, 3.0 * t * t * y, t ** 3]
    return sum(w[i][:, None] * curves[:, i] for i in range(4))


def _cubic_d(curves, t):
    y = 1.0 - t
    d = 3.0 * (curves[:, 1:] - curves[:, :-1])  # (K, 3, 3): the derivative's quadratic control points
    w = [y * y, 2.0 * t * y, t * t]
    return sum(w[i][:, None] * d[:, i] for i in range(3))


def t_junctions(control_points, errors, slack):
    """Where patch corners lie inside another patch's side (the quadtree's T-junctions, also
    across ptex faces): for each patch and side (as _sides) the sorted fractions along the side,
    in (0, 1), of the corners within 1.5 x (the side's patch error + the largest error of the
    corner's patches) + slack of it (neighbours differ by at most the sum of their errors). A face
    gets a vertex there, so that sewing pairs its side with the shorter sides of its neighbours."""
    np = numpy()
    n = len(control_points)
    sides = _sides(control_points).reshape(-1, 4, 3)               # (4N, 4, 3)
    corners = sides[:, 0]                                          # every patch corner (4N, 3)
    corner_errors = np.repeat(np.asarray(errors, dtype=np.float64), 4)
    scale = max(float(np.abs(corners).max()), 1.0) if n else 1.0
    keys = np.round(corners / (scale * 1e-12)).astype(np.int64)
    _, first, inverse = np.unique(keys, axis=0, return_index=True, return_inverse=True)
    points = corners[first]                                        # distinct corners (M, 3)
    point_errors = np.zeros(len(points))
    np.maximum.at(point_errors, inverse.reshape(-1), corner_errors)
    tolerance = 1.5 * (float(np.max(errors)) + float(point_errors.max())) + slack if n else slack
    lengths = np.linalg.norm(sides[:, 3] - sides[:, 0], axis=1)
    cell = max(float(np.median(lengths)) if n else 1.0, 1e-300)
    grid = {}
    for index, key in enumerate(map(tuple, np.floor(points / cell).astype(np.int64))):
        grid.setdefault(key, []).append(index)
    samples_t = np.linspace(0.0, 1.0, 33)
    y = 1.0 - samples_t
    basis = np.stack([y ** 3, 3 * samples_t * y * y, 3 * samples_t ** 2 * y, samples_t ** 3], axis=1)  # (33, 4)
    out = [[[] for _ in range(4)] for _ in range(n)]
    lo_all = sides.min(axis=1) - tolerance
    hi_all = sides.max(axis=1) + tolerance
    for k in range(len(sides)):
        lo = np.floor(lo_all[k] / cell).astype(np.int64)
        hi = np.floor(hi_all[k] / cell).astype(np.int64)
        candidates = []
        for a in range(lo[0], hi[0] + 1):
            for b in range(lo[1], hi[1] + 1):
                for c in range(lo[2], hi[2] + 1):
                    candidates.extend(grid.get((a, b, c), ()))
        if len(candidates) <= 2:
            continue  # its own two corners
        candidates = np.array(candidates)
        pts = points[candidates]
        inside = np.all((pts >= lo_all[k]) & (pts <= hi_all[k]), axis=1)
        pts, candidates = pts[inside], candidates[inside]
        local = 1.5 * (corner_errors[k] + point_errors[candidates]) + slack   # this pair's tolerance
        ends = sides[k, [0, 3]]
        far = np.min(np.linalg.norm(pts[:, None, :] - ends[None], axis=2), axis=1) > local
        pts, local = pts[far], local[far]
        if not len(pts):
            continue
        curve = basis @ sides[k]                                        # (33, 3)
        d = np.linalg.norm(pts[:, None, :] - curve[None], axis=2)       # (K, 33)
        step = float(np.linalg.norm(np.diff(curve, axis=0), axis=1).max())
        near = d.min(axis=1) <= local + step
        if not near.any():
            continue
        pts, local = pts[near], local[near]
        t = samples_t[np.argmin(d[near], axis=1)]
        curves = np.repeat(sides[k][None], len(pts), axis=0)
        for _ in range(8):  # Newton on (B(t) - p) . B'(t) = 0
            diff = _cubic(curves, t) - pts
            d1 = _cubic_d(curves, t)
            dt = 1e-7
            g = np.sum(diff * d1, axis=1)
            g2 = (np.sum((_cubic(curves, t + dt) - pts) * _cubic_d(curves, t + dt), axis=1) - g) / dt
            t = np.clip(t - g / np.where(np.abs(g2) > 1e-300, g2, 1e-300), 0.0, 1.0)
        dist = np.linalg.norm(_cubic(curves, t) - pts, axis=1)
        keep = (dist <= local) & (t > 1e-9) & (t < 1.0 - 1e-9)
        if keep.any():
            out[k // 4][k % 4] = sorted(set(np.round(t[keep], 12).tolist()))
    return out


def bezier_surface(control_points):
    """The bicubic Bezier patch `control_points` (4, 4, 3) ([i, j]: weight B_i(s) B_j(t)) as a
    Part.BSplineSurface of degree 3 with knots [0, 1] of multiplicity 4; (u, v) = (s, t)."""
    poles = [[FreeCAD.Vector(*map(float, control_points[i, j])) for j in range(4)] for i in range(4)]
    surface = Part.BSplineSurface()
    surface.buildFromPolesMultsKnots(poles, [4, 4], [4, 4], [0.0, 1.0], [0.0, 1.0], False, False, 3, 3)
    return surface


def square_face(surface, splits=None):
    """A face on `surface` (a Part surface on [0, 1]^2) whose boundary is the whole square, with
    extra vertices at `splits`: per side (0: v = 0, u 0 -> 1; 1: u = 1, v 0 -> 1; 2: v = 1, u 1 -> 0;
    3: u = 0, v 1 -> 0, counter-clockwise in (u, v)) the sorted fractions in (0, 1) along that walk."""
    if not splits or not any(splits):
        return surface.toShape()
    V2 = FreeCAD.Base.Vector2d
    corners = ((0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0))
    edges = []
    for side in range(4):
        a, b = corners[side], corners[(side + 1) % 4]
        fractions = [0.0] + list(splits[side]) + [1.0]
        at = [V2(a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1])) for f in fractions]
        edges.extend(Part.Geom2d.Line2dSegment(p, q).toShape(surface) for p, q in zip(at, at[1:]))
    return Part.Face(surface, Part.Wire(edges))


def bezier_face(control_points, splits=None):
    """A face on the whole Bezier patch `control_points` (see bezier_surface), with extra vertices
    at `splits` (as t_junctions / square_face)."""
    return square_face(bezier_surface(control_points), splits)


def sew(faces, tolerance, cut_free_edges=True):
    """BRepBuilderAPI_Sewing of `faces` with `tolerance` (model units), through a Surface::Sewing
    feature in a hidden scratch document (FreeCAD 0.20's Shape.sewShape() ignores its tolerance)."""
    import Surface  # noqa: F401  (registers Surface::Sewing)
    doc = FreeCAD.newDocument("CageKitSewing", hidden=True, temp=True)
    try:
        source = doc.addObject("Part::Feature", "Faces")
        source.Shape = Part.makeCompound(faces)
        sewing = doc.addObject("Surface::Sewing", "Sewing")
        sewing.ShapeList = [(source, ["Face%d" % (i + 1) for i in range(len(faces))])]
        sewing.Tolerance = float(tolerance)
        sewing.SewingOption = True
        sewing.DegenerateShape = True
        sewing.CutFreeEdges = bool(cut_free_edges)
        sewing.Nonmanifold = False
        doc.recompute()
        if not sewing.isValid() or sewing.Shape.isNull():
            raise WorkbenchError("sewing the %d faces failed" % len(faces))
        return sewing.Shape.copy()
    finally:
        FreeCAD.closeDocument(doc.Name)


def shell_or_solid(faces, sew_tolerance):
    """Sews `faces` with `sew_tolerance` (model units) and returns a dict: shape (a Part.Solid,
    outward, when the faces sew into one closed shell; else that shell, or the sewn compound),
    closed, shells (count), valid (Shape.isValid(), BRepCheck), check (None, or the message of
    Shape.check(True) when invalid), seconds {"sew", "solid"} (the solid's time includes the check)."""
    t = time.perf_counter()
    sewn = sew(faces, sew_tolerance)
    out = solid_of(sewn, len(faces))
    out["seconds"]["sew"] = time.perf_counter() - t - out["seconds"]["solid"]
    return out


def solid_of(sewn, face_count):
    """shell_or_solid's second half, without a document (safe on a worker thread): the sewn
    shape -> a Part.Solid (outward) when it is one closed shell of all `face_count` faces, else
    the shell (or the sewn shape); BRepCheck."""
    t = time.perf_counter()
    shells = sewn.Shells
    closed = False
    if len(shells) == 1 and len(shells[0].Faces) == face_count and shells[0].isClosed():
        shape = Part.Solid(shells[0])
        if shape.Volume < 0:
            shape.reverse()
        closed = True
    elif len(shells) == 1 and len(shells[0].Faces) == face_count:
        shape = shells[0]
    else:
        shape = sewn
    valid = bool(shape.isValid())
    message = None
    if not valid:
        try:
            shape.check(True)
        except Exception as e:  # BRepCheck's findings
            message = str(e).strip() or type(e).__name__
    return {"shape": shape, "closed": closed, "shells": len(shells), "valid": valid, "check": message,
            "seconds": {"sew": 0.0, "solid": time.perf_counter() - t}}


def patches_shape(control_points, errors, sew_tolerance, slack=0.0):
    """(shape, closed): one face per patch ((N, 4, 4, 3) control points, (N,) errors), with
    vertices at the T-junctions, sewn with `sew_tolerance` (model units) into shells; one closed
    shell becomes a solid (outward)."""
    splits = t_junctions(control_points, errors, slack)
    faces = [bezier_face(cp, sp) for cp, sp in zip(control_points, splits)]
    result = shell_or_solid(faces, sew_tolerance)
    return result["shape"], result["closed"]


# --- merged B-spline surfaces (cagekit_limit_surfaces_*) -------------------------------------------------
MODES = ("bspline", "patches")


def knots_and_mults(knots):
    """(distinct knots, multiplicities) of a full knot vector (end knots repeated degree + 1 times),
    as Part.BSplineSurface.buildFromPolesMultsKnots wants them."""
    distinct, mults = [], []
    for x in (float(k) for k in knots):
        if distinct and x == distinct[-1]:
            mults[-1] += 1
        else:
            distinct.append(x)
            mults.append(1)
    return distinct, mults


def part_bspline_surface(surface):
    """A Part.BSplineSurface equal to a cagekit BSplineSurface: the same degrees and knots (as
    distinct knots and multiplicities), poles[i][j] = control point (i, j) = cagekit's
    control_points[j, i] (i along u); not periodic, not rational. (u, v) is the SDK surface's,
    i.e. the ptex location (surface.ptex_face, u, v) of the limit surface."""
    uk, um = knots_and_mults(surface.knots_u)
    vk, vm = knots_and_mults(surface.knots_v)
    cp = surface.control_points  # (num_v, num_u, 3): [j, i] has weight N_i(u) N_j(v)
    V = FreeCAD.Vector
    poles = [[V(float(cp[j, i, 0]), float(cp[j, i, 1]), float(cp[j, i, 2])) for j in range(cp.shape[0])]
             for i in range(cp.shape[1])]
    out = Part.BSplineSurface()
    out.buildFromPolesMultsKnots(poles, um, vm, uk, vk, False, False, int(surface.degree_u), int(surface.degree_v))
    return out


_GRID_BASES = {}


def _grid_basis(knots, degree, count):
    """cagekit's bspline_basis (the SDK surfaces' own evaluation) at count equidistant parameters
    over the knots' range, memoised (the SDK's surfaces share a few knot vectors)."""
    np = numpy()
    key = (tuple(float(k) for k in knots), int(degree), int(count))
    basis = _GRID_BASES.get(key)
    if basis is None:
        if len(_GRID_BASES) > 256:
            _GRID_BASES.clear()
        import importlib
        bspline_basis = importlib.import_module(sdk().__name__ + ".limit_surfaces").bspline_basis
        basis = _GRID_BASES[key] = bspline_basis(np.array(key[0]), degree, np.linspace(key[0][0], key[0][-1], count))
    return basis


def bspline_grid(knots_u, knots_v, degree_u, degree_v, poles, count=33):
    """(count, count, 3) points of a non-rational B-spline surface (full knot vectors, poles
    (n_u, n_v, 3)) on a count x count grid of its parameter domain ([i, j]: u index i, v index j)."""
    np = numpy()
    nu = _grid_basis(knots_u, degree_u, count)
    nv = _grid_basis(knots_v, degree_v, count)
    return np.stack([nu @ poles[:, :, k] @ nv.T for k in range(3)], axis=-1)


def part_surface_grid(surface, count=33):
    """bspline_grid of a non-rational Part.BSplineSurface, from its poles and knots."""
    np = numpy()
    poles = np.array([[tuple(p) for p in row] for row in surface.getPoles()])  # (NbUPoles, NbVPoles, 3)
    return bspline_grid(surface.UKnotSequence, surface.VKnotSequence, surface.UDegree, surface.VDegree, poles, count)


def sdk_surface_grid(surface, count=33):
    """bspline_grid of a cagekit BSplineSurface (the points of part_bspline_surface's surface)."""
    np = numpy()
    poles = np.transpose(np.asarray(surface.control_points, dtype=np.float64), (1, 0, 2))  # [i along u, j, 3]
    return bspline_grid(np.asarray(surface.knots_u, dtype=np.float64), np.asarray(surface.knots_v, dtype=np.float64),
                        int(surface.degree_u), int(surface.degree_v), poles, count)


def remove_knots(surface, tolerance, before=None):
    """Removes the interior knots of a Part.BSplineSurface whose removal moves it by at most a step
    tolerance (model units; OCCT checks each removal against the surface before it, so the moves
    add up): first `tolerance` itself, then half as much while the result, measured against the
    input on a 33 x 33 grid of its parameter domain (removal keeps the parametrisation), is further
    than `tolerance` (at most four halvings; otherwise the input is kept). The same rule as the
    CLI's export-surfaces --knot-removal. `before`: part_surface_grid(surface) when the caller has
    it. Returns (surface, measured distance)."""
    np = numpy()
    if surface.NbUKnots <= 2 and surface.NbVKnots <= 2:
        return surface, 0.0
    before = part_surface_grid(surface) if before is None else before
    step = float(tolerance)
    for _ in range(5):
        s = surface.copy()
        for direction in ("U", "V"):
            remove = getattr(s, "remove%sKnot" % direction)
            i = 2
            while i < getattr(s, "Nb%sKnots" % direction):
                if not remove(i, 0, step):
                    i += 1
        if s.NbUPoles * s.NbVPoles == surface.NbUPoles * surface.NbVPoles:
            break
        moved = float(np.linalg.norm(part_surface_grid(s) - before, axis=2).max())
        if moved <= tolerance:
            return s, moved
        step *= 0.5
    return surface, 0.0


def _side_uv(side, t):
    """(n, 2) (u, v) of side `side` (0: v = 0, 1: u = 1, 2: v = 1, 3: u = 0) at its parameter t."""
    np = numpy()
    t = np.asarray(t, dtype=np.float64)
    zero, one = np.zeros_like(t), np.ones_like(t)
    u = {0: t, 1: one, 2: t, 3: zero}[side]
    v = {0: zero, 1: t, 2: one, 3: t}[side]
    return np.stack([u, v], axis=1)


def side_splits(surface, eps=1e-12):
    """Per side of a cagekit BSplineSurface, the fractions (0, 1) along the counter-clockwise walk
    (as square_face) where a neighbour's stretch [t0, t1] begins or ends: there the face needs a
    vertex, so that sewing pairs the side with each neighbour (a quad beside an n-gon's ptex faces)."""
    out = []
    for side in range(4):
        ts = set()
        for n in surface.sides[side].neighbours:
            ts.update((float(n.t0), float(n.t1)))
        inner = sorted(t for t in ts if eps < t < 1.0 - eps)
        out.append(inner if side < 2 else sorted(1.0 - t for t in inner))
    return out


def border_gaps(surfaces, samples=9):
    """(S, 4) array: the largest distance between each side of each cagekit BSplineSurface and the
    neighbours' sides at corresponding parameters (`samples` points per neighbour stretch; 0 on a
    side without neighbours). The SDK makes shared borders the same curves: this measures it."""
    np = numpy()
    n = len(surfaces)
    s = np.linspace(0.0, 1.0, samples)
    requests = [[] for _ in range(n)]  # per surface: (uv (m, 2), global sample rows, role 0 (own) / 1 (neighbour))
    owner, count = [], 0
    for a, sa in enumerate(surfaces):
        for side in range(4):
            for nb in sa.sides[side].neighbours:
                rows = np.arange(count, count + samples)
                count += samples
                owner.extend([(a, side)] * samples)
                requests[a].append((_side_uv(side, nb.t0 + s * (nb.t1 - nb.t0)), rows, 0))
                requests[int(nb.surface)].append((_side_uv(int(nb.side), nb.n0 + s * (nb.n1 - nb.n0)), rows, 1))
    gaps = np.zeros((n, 4))
    if not count:
        return gaps
    points = np.zeros((2, count, 3))
    for c, blocks in enumerate(requests):
        if blocks:
            values = surfaces[c].evaluate(np.concatenate([b[0] for b in blocks]))
            at = 0
            for uv, rows, role in blocks:
                points[role, rows] = values[at:at + len(uv)]
                at += len(uv)
    owner = np.array(owner)
    np.maximum.at(gaps, (owner[:, 0], owner[:, 1]), np.linalg.norm(points[0] - points[1], axis=1))
    return gaps


def _sample_uv(count, surface_count, seed):
    """`count` (surface index, (u, v)) pairs: random, an eighth of them at corners."""
    np = numpy()
    if count <= 0 or surface_count <= 0:
        return np.zeros(0, dtype=np.int64), np.zeros((0, 2))
    rng = np.random.default_rng(seed)
    k = rng.integers(0, surface_count, count)
    uv = rng.random((count, 2))
    uv[:count // 8] = np.round(uv[:count // 8])
    return k, uv


@contextlib.contextmanager
def _sdk_cage(cage, progress, feature, missing):
    """Yields (cagekit module, cagekit.Cage) for `cage` (a cagekit.Cage; or a CageKit cage object
    or cage_arrays()' dict, converted for the duration of the block and closed after it);
    WorkbenchError when the installed cagekit package lacks `feature` (`missing` says what to do)."""
    ck = sdk()
    if not hasattr(ck, feature):
        raise WorkbenchError("the cagekit package at %s has no %s" % (os.path.dirname(ck.__file__), missing))
    owned = not isinstance(cage, ck.Cage)
    if owned:
        ctx = ck.Context(progress=progress)
        cage = cage_from_arrays(cage, ctx) if isinstance(cage, dict) else cage_from_object(cage, ctx)
    try:
        yield ck, cage
    finally:
        if owned:
            cage.close()


def bspline_sdk(cage, tolerance=1e-4, max_level=5, samples=256, progress=None, knot_removal=None):
    """bspline_faces' SDK stage (no FreeCAD object touched when `cage` is a cagekit.Cage or
    cage_arrays()' dict: usable on a worker thread): a dict mode, sdk_surfaces, info, tolerance,
    knot_removal (the fraction of the diagonal bspline_part's knot removal may move a surface:
    `knot_removal`, or a tenth of `tolerance` when None; 0: no removal), samples, seconds {"limit"}."""
    if knot_removal is None:  # a bad tolerance is the SDK's to report, with its own message
        knot_removal = 0.1 * float(tolerance) if 0.0 < float(tolerance) < float("inf") else 0.0
    knot_removal = float(knot_removal)
    if not (0.0 <= knot_removal < float("inf")):
        raise WorkbenchError("knot removal must be a finite fraction of the diagonal >= 0, not %r" % knot_removal)
    np = numpy()
    with _sdk_cage(cage, progress, "LimitSurfaces", "merged B-spline surfaces (cagekit_limit_surfaces_*): "
                   "update it and libcagekit, or use mode 'patches'") as (ck, cage):
        t = time.perf_counter()
        with ck.LimitSurfaces(cage, tolerance=float(tolerance), max_level=int(max_level)) as limit:
            info = limit.info
            sdk_surfaces = list(limit)
        t_limit = time.perf_counter() - t
        k, uv = _sample_uv(int(samples), len(sdk_surfaces), 11)
        with cage.surface() as evaluator:
            ptex = np.array([sdk_surfaces[int(i)].ptex_face for i in k], dtype=np.uint32)
            points = evaluator.evaluate(ptex, uv).position if len(k) else np.zeros((0, 3))
    return {"mode": "bspline", "sdk_surfaces": sdk_surfaces, "info": info, "tolerance": float(tolerance),
            "knot_removal": knot_removal, "samples": (k, points), "seconds": {"limit": t_limit}}


def bspline_part(stage):
    """bspline_faces' FreeCAD stage: Part surfaces and faces of bspline_sdk's result."""
    t = time.perf_counter()
    sdk_surfaces, info = stage["sdk_surfaces"], stage["info"]
    diag = float(info.bbox_diagonal)
    gap = float(border_gaps(sdk_surfaces).max()) if sdk_surfaces else 0.0
    surfaces = [part_bspline_surface(s) for s in sdk_surfaces]
    poles_before = sum(p.NbUPoles * p.NbVPoles for p in surfaces)
    removal = float(stage.get("knot_removal", 0.0)) * diag
    moved = 0.0
    if removal > 0:
        # A surface moves by at most what the tolerance leaves it (its two-sided distance to the
        # limit surface grows by at most the move), and keeps its knots when it has no slack.
        limit = float(stage["tolerance"]) * diag
        reduced = [remove_knots(p, min(removal, limit - float(q.error)), sdk_surface_grid(q))
                   if (p.NbUKnots > 2 or p.NbVKnots > 2) and limit - float(q.error) > 0 else (p, 0.0)
                   for p, q in zip(surfaces, sdk_surfaces)]
        surfaces = [p for p, _ in reduced]
        moved = max((d for _, d in reduced), default=0.0)
    faces = [square_face(p, side_splits(s)) for p, s in zip(surfaces, sdk_surfaces)]
    out = dict(stage)
    out.update({"surfaces": surfaces, "faces": faces,
                "counts": {"faces": len(faces), "exact": int(info.exact_count),
                           "approximated": int(info.approximated_count),
                           "over_tolerance": int(info.over_tolerance_count), "ptex_faces": int(info.ptex_face_count),
                           "control_points_before": int(poles_before),
                           "control_points": int(sum(p.NbUPoles * p.NbVPoles for p in surfaces))},
                "max_error_rel": float(info.max_error_rel), "bbox_diagonal": diag,
                "max_knot_removal_deviation_rel": moved / diag if diag > 0 else 0.0,
                "border_gap": gap, "sew_tolerance": max(10.0 * gap + 1e-7 * max(diag, 1e-300), 2.5 * removal),
                "seconds": {"limit": stage["seconds"]["limit"], "faces": time.perf_counter() - t}})
    return out


def bspline_faces(cage, tolerance=1e-4, max_level=5, samples=256, progress=None, knot_removal=None):
    """The limit surface of `cage` (a cagekit.Cage or a CageKit cage object) as the SDK's merged
    B-spline surfaces (cagekit_limit_surfaces_create: one bicubic B-spline with interior knots per
    ptex face; tolerance: fraction of the bounding-box diagonal; max_level: 1..7), in FreeCAD.
    Returns a dict:
      mode "bspline"; surfaces: one Part.BSplineSurface per SDK surface (part_bspline_surface);
      faces: one Part.Face per surface on its whole [0, 1]^2, with vertices where neighbours' stretches
      end (side_splits); info: the SDK's record (surface_count, exact_count, approximated_count,
      over_tolerance_count, folded_count, max_error_rel, max_normal_jump_deg, bbox_diagonal, ...);
      counts {faces, exact, approximated, over_tolerance, ptex_faces}; max_error_rel;
      border_gap: the largest measured distance between shared borders (model units);
      sew_tolerance: 10 x that gap + 1e-7 of the diagonal (model units);
      samples (face index (m,), limit-surface points (m, 3) from cagekit's Surface.evaluate at the
      surfaces' (u, v)) for checks; seconds {"limit", "faces"};
      knot_removal: the interior knots whose removal moves a surface by at most this fraction of the
      diagonal (default a tenth of `tolerance`; 0: none), and by no more than the tolerance leaves
      it (tolerance - its error: a surface within the tolerance stays within it), are removed
      (remove_knots); counts control_points_before /
      control_points, max_knot_removal_deviation_rel (measured on a 33 x 33 grid per surface); the
      sewing tolerance is at least 2.5 x the removal's. (bspline_sdk, then bspline_part.)"""
    return bspline_part(bspline_sdk(cage, tolerance, max_level, samples, progress, knot_removal))


def patch_sdk(cage, tolerance=1e-4, max_depth=8, samples=256, progress=None):
    """patch_faces' SDK stage (as bspline_sdk)."""
    np = numpy()
    with _sdk_cage(cage, progress, "LimitPatches", "limit patches (cagekit_limit_patches_create): "
                   "update it and libcagekit") as (ck, cage):
        t = time.perf_counter()
        with ck.LimitPatches(cage, tolerance=float(tolerance), max_depth=int(max_depth)) as patches:
            info = patches.info
            control_points = patches.control_points
            errors = patches.errors
            exact = patches.exact
            k, st = _sample_uv(int(samples), len(control_points), 11)
            ptex, uv = patches.ptex_locations(k, st) if len(k) else (np.zeros(0, np.uint32), np.zeros((0, 2)))
        t_limit = time.perf_counter() - t
        with cage.surface() as evaluator:
            points = evaluator.evaluate(ptex, uv).position if len(k) else np.zeros((0, 3))
    return {"mode": "patches", "sdk_surfaces": (control_points, errors, exact), "info": info,
            "tolerance": float(tolerance), "samples": (k, points), "seconds": {"limit": t_limit}}


def patch_part(stage):
    """patch_faces' FreeCAD stage: Bezier surfaces and faces of patch_sdk's result."""
    t = time.perf_counter()
    control_points, errors, exact = stage["sdk_surfaces"]
    info = stage["info"]
    diag = float(info.bbox_diagonal)
    splits = t_junctions(control_points, errors, 1e-9 * diag)
    surfaces = [bezier_surface(cp) for cp in control_points]
    faces = [square_face(s, sp) for s, sp in zip(surfaces, splits)]
    out = dict(stage)
    out.update({"surfaces": surfaces, "faces": faces,
                "counts": {"faces": len(faces), "exact": int(info.exact_count),
                           "approximated": int(info.approximated_count),
                           "over_tolerance": int(info.over_tolerance_count), "ptex_faces": None},
                "max_error_rel": float(info.max_error_rel), "bbox_diagonal": diag,
                "border_gap": float(info.max_error), "sew_tolerance": sew_tolerance_for(control_points, info),
                "seconds": {"limit": stage["seconds"]["limit"], "faces": time.perf_counter() - t}})
    return out


def patch_faces(cage, tolerance=1e-4, max_depth=8, samples=256, progress=None):
    """The limit surface of `cage` (a cagekit.Cage or a CageKit cage object) as one Bezier face per
    patch of cagekit_limit_patches_create (the workbench's first mode), with vertices at the
    quadtree's T-junctions. The same dict as bspline_faces (mode "patches"; sdk_surfaces: the
    patches' (control points, errors, exact); border_gap: the largest patch error; sew_tolerance
    as sew_tolerance_for). (patch_sdk, then patch_part.)"""
    return patch_part(patch_sdk(cage, tolerance, max_depth, samples, progress))


def surface_sdk(cage, tolerance=1e-4, mode="bspline", max_level=5, max_depth=8, samples=256, progress=None,
                knot_removal=None):
    """The SDK stage of surface_shape (bspline_sdk or patch_sdk by `mode`)."""
    if mode not in MODES:
        raise WorkbenchError("mode must be one of %s, not %r" % (", ".join(MODES), mode))
    if mode == "bspline":
        return bspline_sdk(cage, tolerance, max_level, samples, progress, knot_removal)
    return patch_sdk(cage, tolerance, max_depth, samples, progress)


def surface_faces(stage):
    """The Part faces of surface_sdk's result (bspline_part or patch_part)."""
    return bspline_part(stage) if stage["mode"] == "bspline" else patch_part(stage)


def surface_sew(result):
    """surface_finish's first half (needs a scratch document: FreeCAD's main thread): the faces
    sewn (result["sewn"], seconds "sew")."""
    t = time.perf_counter()
    result["sewn"] = sew(result["faces"], result["sew_tolerance"])
    result["seconds"]["sew"] = time.perf_counter() - t
    return result


def surface_solid(result):
    """surface_finish's second half (no document: safe on a worker thread): surface_sew's shape
    -> solid, BRepCheck; the totals."""
    sewn = solid_of(result.pop("sewn"), len(result["faces"]))
    t_sew = result["seconds"]["sew"]
    result["seconds"].update(sewn.pop("seconds"))
    result["seconds"]["sew"] = t_sew
    result.update(sewn)
    result["step"], result["step_bytes"], result["seconds"]["step"] = None, 0, 0.0
    result["seconds"]["total"] = sum(result["seconds"][key] for key in ("limit", "faces", "sew", "solid"))
    return result


def surface_finish(result, step=None):
    """Sews surface_faces' result (shell_or_solid) [and writes STEP]: surface_shape's dict."""
    sewn = shell_or_solid(result["faces"], result["sew_tolerance"])
    seconds = result["seconds"]
    seconds.update(sewn.pop("seconds"))
    result.update(sewn)
    result["step"], result["step_bytes"], seconds["step"] = None, 0, 0.0
    if step is not None:
        t = time.perf_counter()
        result["step"] = export_step(result["shape"], step)
        seconds["step"] = time.perf_counter() - t
        result["step_bytes"] = os.path.getsize(result["step"])
    seconds["total"] = sum(seconds[key] for key in ("limit", "faces", "sew", "solid", "step"))
    return result


def surface_shape(cage, tolerance=1e-4, mode="bspline", max_level=5, max_depth=8, step=None, samples=256,
                  progress=None, knot_removal=None):
    """limit surface -> faces -> sewn shell -> solid (when closed) [-> STEP], without a document.
    cage: a cagekit.Cage or a CageKit cage object; mode "bspline" (default: bspline_faces, one face
    per merged SDK surface, max_level) or "patches" (patch_faces, one Bezier face per SDK patch,
    max_depth); step: a path to write (export_step, atomic) or None. Returns the dict of
    bspline_faces / patch_faces plus shell_or_solid's (shape, closed, shells, valid, check),
    step / step_bytes when written, and seconds {"limit", "faces", "sew", "solid", "step",
    "total"} (total: limit -> sewn solid [-> STEP]). knot_removal (mode "bspline"): as bspline_faces."""
    stage = surface_sdk(cage, tolerance, mode, max_level, max_depth, samples, progress, knot_removal)
    return surface_finish(surface_faces(stage), step)


def step_round_trip(path, result):
    """Reads the STEP file `path` back (Part.read) and compares it with `result` (surface_shape's):
    returns a dict faces, solids, shells, closed (one closed shell), valid, matched (each face of
    result["surfaces"] is the re-imported face whose surface has the nearest centre, a bijection),
    centre_gap (largest such centre distance, model units), max_distance (largest distToShape of
    result["samples"]' limit points to their matched re-imported face, model units), bound
    (tolerance x diagonal + the sewing tolerance), within (max_distance <= bound), seconds
    {"read", "distance"}."""
    np = numpy()
    t = time.perf_counter()
    back = Part.read(path)
    t_read = time.perf_counter() - t
    faces = back.Faces
    out = {"faces": len(faces), "solids": len(back.Solids), "shells": len(back.Shells),
           "closed": len(back.Shells) == 1 and back.Shells[0].isClosed(), "valid": bool(back.isValid())}

    def centre(surface):
        u0, u1, v0, v1 = surface.bounds()
        p = surface.value(0.5 * (u0 + u1), 0.5 * (v0 + v1))
        return (p.x, p.y, p.z)

    t = time.perf_counter()
    mine = np.array([centre(s) for s in result["surfaces"]]).reshape(-1, 3)
    theirs = np.array([centre(f.Surface) for f in faces]).reshape(-1, 3)
    match = np.zeros(len(mine), dtype=np.int64)
    gap = np.zeros(len(mine))
    if len(theirs):
        for lo in range(0, len(mine), 256):
            d = np.linalg.norm(mine[lo:lo + 256, None, :] - theirs[None, :, :], axis=2)
            match[lo:lo + 256] = np.argmin(d, axis=1)
            gap[lo:lo + 256] = d[np.arange(len(d)), match[lo:lo + 256]]
    out["matched"] = len(theirs) == len(mine) and len(set(match.tolist())) == len(mine)
    out["centre_gap"] = float(gap.max()) if len(gap) else 0.0
    k, points = result["samples"]
    distances = np.array([faces[int(match[i])].distToShape(Part.Vertex(FreeCAD.Vector(*map(float, p))))[0]
                          for i, p in zip(k, points)]) if len(theirs) and len(k) else np.zeros(0)
    out["max_distance"] = float(distances.max()) if len(distances) else 0.0
    out["bound"] = result["tolerance"] * result["bbox_diagonal"] + result["sew_tolerance"]
    out["within"] = out["matched"] and bool(np.all(distances <= out["bound"]))
    out["seconds"] = {"read": t_read, "distance": time.perf_counter() - t}
    return out


_SURFACE_PROPERTIES = (
    ("Cage", "App::PropertyLink", "The cage whose limit surface this is (a change of its control mesh recomputes it)"),
    ("Mode", "App::PropertyEnumeration", "bspline: one B-spline face per merged SDK surface (per ptex face); "
                                         "patches: one Bezier face per SDK patch"),
    ("Tolerance", "App::PropertyLength", "Largest distance allowed between an approximated face and the limit "
                                         "surface (document units; the SDK gets it as a fraction of the cage's "
                                         "bounding-box diagonal: ToleranceRel)"),
    ("MaxLevel", "App::PropertyInteger", "bspline mode: largest knot level tried (1..7)"),
    ("MaxDepth", "App::PropertyInteger", "patches mode: quadtree depth allowed for approximated regions"),
    ("ToleranceRel", "App::PropertyFloat", "Tolerance / bbox diagonal of the control points, as given to the SDK"),
    ("PatchCount", "App::PropertyInteger", "Faces: SDK surfaces (bspline) or SDK patches (patches)"),
    ("ExactPatches", "App::PropertyInteger", "Faces that are the limit surface itself"),
    ("ApproximatedPatches", "App::PropertyInteger", "Faces that approximate it"),
    ("OverTolerancePatches", "App::PropertyInteger", "Approximated faces beyond the tolerance (or folded)"),
    ("MaxErrorRel", "App::PropertyFloat", "Largest measured distance / bbox diagonal"),
    ("MaxNormalJumpDeg", "App::PropertyFloat", "bspline mode: largest normal jump across smooth borders (deg)"),
    ("BBoxDiagonal", "App::PropertyFloat", "Bounding-box diagonal of the control points"),
    ("SewTolerance", "App::PropertyFloat", "Tolerance used to sew the faces (model units)"),
    ("Closed", "App::PropertyBool", "The sewn shell is closed (the Shape is a solid)"),
    ("Valid", "App::PropertyBool", "The Shape passes BRepCheck (Shape.isValid())"),
    ("Seconds", "App::PropertyFloat", "Time of limit surface -> faces -> sewn shell / solid (s)"),
    ("InputKey", "App::PropertyString", "Digest of the inputs the surface was last computed from"))
_SURFACE_INPUTS = ("Cage", "Mode", "Tolerance", "MaxLevel", "MaxDepth")


def _add_surface_properties(obj):
    for name, kind, text in _SURFACE_PROPERTIES:
        _property(obj, kind, name, text, read_only=name not in _SURFACE_INPUTS, hidden=name == "InputKey")
    if not obj.getEnumerationsOfProperty("Mode"):
        obj.Mode = list(MODES)


def bbox_diagonal(arrays):
    """The bounding-box diagonal of cage_arrays()' control points (the SDK's reference length)."""
    np = numpy()
    pos = arrays["positions"]
    return float(np.linalg.norm(pos.max(axis=0) - pos.min(axis=0))) if len(pos) else 0.0


def _cage_digest(a):
    return _digest(a["positions"], a["sizes"], a["flat"], a["creases"], a["crease_sharpness"], a["corners"],
                   a["corner_sharpness"], a["holes"], a["boundary_rule"])


def surface_input_key(obj, arrays=None):
    """The digest of what the surface object's computation depends on: its cage's control mesh
    and tags, Mode, Tolerance, MaxLevel, MaxDepth."""
    cage = getattr(obj, "Cage", None)
    if cage is None:
        return ""
    a = arrays if arrays is not None else cage_arrays(cage)
    return _digest(_cage_digest(a), str(obj.Mode), float(obj.Tolerance.Value), int(obj.MaxLevel), int(obj.MaxDepth))


def surface_options(obj, arrays=None):
    """The keyword arguments of surface_sdk from a surface object's inputs: the tolerance
    (a length) as the fraction of the cage's bounding-box diagonal the SDK takes."""
    a = arrays if arrays is not None else cage_arrays(obj.Cage)
    diag = bbox_diagonal(a)
    length = float(obj.Tolerance.Value)
    return {"tolerance": length / diag if diag > 0 else math.nan, "mode": str(obj.Mode),
            "max_level": int(obj.MaxLevel), "max_depth": int(obj.MaxDepth)}


class SurfaceProxy:
    """The Proxy of a parametric limit surface (Part::FeaturePython, group CageKit). execute():
    when its inputs (the linked Cage's control mesh and tags, Mode, Tolerance, MaxLevel, MaxDepth)
    differ from those of the last computation (InputKey), the surface is computed again
    (surface_shape); otherwise nothing changes. Serialisable: no state besides the properties."""

    Type = "CageKitSurface"

    def __init__(self, obj):
        obj.Proxy = self
        _add_surface_properties(obj)

    def onDocumentRestored(self, obj):
        _add_surface_properties(obj)

    def execute(self, obj):
        if obj.Cage is None:
            return
        a = cage_arrays(obj.Cage)
        key = surface_input_key(obj, a)
        if key == obj.InputKey or _in_background(obj, "surface"):
            return
        FreeCAD.Console.PrintMessage("CageKit: recomputing %r\n" % obj.Label)
        o = surface_options(obj, a)
        write_surface(obj, surface_shape(a, samples=0, **o), a)

    def __getstate__(self):
        return None

    def __setstate__(self, state):
        return None


def write_surface(obj, result, arrays):
    """Writes surface_shape's result into the surface object (Shape, figures, InputKey)."""
    info = result["info"]
    mode = result["mode"]
    counts = result["counts"]
    obj.ToleranceRel = float(result["tolerance"])
    obj.PatchCount = counts["faces"]
    obj.ExactPatches = counts["exact"]
    obj.ApproximatedPatches = counts["approximated"]
    obj.OverTolerancePatches = counts["over_tolerance"]
    obj.MaxErrorRel = result["max_error_rel"]
    obj.MaxNormalJumpDeg = float(info.max_normal_jump_deg) if mode == "bspline" else 0.0
    obj.BBoxDiagonal = result["bbox_diagonal"]
    obj.SewTolerance = float(result["sew_tolerance"])
    obj.Closed = bool(result["closed"])
    obj.Valid = bool(result["valid"])
    obj.Seconds = float(result["seconds"]["total"])
    obj.Shape = result["shape"]
    obj.InputKey = surface_input_key(obj, arrays)
    s = result["seconds"]
    FreeCAD.Console.PrintMessage(
        "CageKit: %r (%s): %d faces (%d exact, %d approximated, max error %.2g of the diagonal), %s%s, "
        "%.1f s (limit %.1f, faces %.1f, sewing %.1f, solid %.1f)\n"
        % (obj.Label, mode, counts["faces"], counts["exact"], counts["approximated"], result["max_error_rel"],
           "closed solid" if result["closed"] else "open shell", "" if result["valid"] else " (INVALID)",
           s["total"], s["limit"], s["faces"], s["sew"], s["solid"]))
    if counts["over_tolerance"]:
        FreeCAD.Console.PrintWarning("CageKit: %d faces exceed the tolerance or fold (max %s %d reached)\n"
                                     % (counts["over_tolerance"], "level" if mode == "bspline" else "depth",
                                        obj.MaxLevel if mode == "bspline" else obj.MaxDepth))
    if not result["valid"]:
        FreeCAD.Console.PrintWarning("CageKit: the shape fails BRepCheck: %s\n" % result["check"])


def surface_of(cage_obj):
    """The parametric limit surface linked to `cage_obj`, or None."""
    for o in cage_obj.Document.Objects:
        if _has_proxy(o, SurfaceProxy) and getattr(o, "Cage", None) is cage_obj:
            return o
    return None


def surface_request(cage_obj, tolerance=1e-4, mode="bspline", max_level=5, max_depth=8, length=None):
    """(cage_arrays(cage_obj), surface_sdk's keyword arguments, the tolerance as a length): the
    tolerance is `length` (document units) when given, else `tolerance` (a fraction of the
    bounding-box diagonal of the control points)."""
    a = cage_arrays(cage_obj)
    diag = bbox_diagonal(a)
    if length is not None:
        length = float(length)
        tolerance = length / diag if diag > 0 else math.nan
    else:
        tolerance = float(tolerance)
        length = tolerance * diag
    return a, {"tolerance": tolerance, "mode": mode, "max_level": int(max_level), "max_depth": int(max_depth)}, length


def apply_surface(cage_obj, result, arrays, length, max_level, max_depth, doc=None):
    """Makes (or updates) the parametric surface '<cage>_surface' of `cage_obj` with surface_shape's
    `result` computed from `arrays` (one undo step)."""
    doc = doc or cage_obj.Document
    with transaction(doc, "CageKit: limit surface"):
        obj = surface_of(cage_obj)
        if obj is None:
            obj = doc.addObject("Part::FeaturePython", "LimitSurface")
            SurfaceProxy(obj)
            if FreeCAD.GuiUp:
                _attach_view_provider(obj, "surface")
            obj.Label = cage_obj.Label + "_surface"
        obj.Cage = cage_obj
        obj.Mode = result["mode"]
        obj.Tolerance = float(length)
        obj.MaxLevel = int(max_level)
        obj.MaxDepth = int(max_depth)
        write_surface(obj, result, arrays)
        doc.recompute()
    return obj


def limit_surface(cage_obj, tolerance=1e-4, max_depth=8, progress=None, doc=None, mode="bspline", max_level=5,
                  length=None):
    """Makes (or updates) the parametric surface '<cage>_surface' (SurfaceProxy: it recomputes when
    the cage or its options change): the cage's limit surface as faces sewn into a shell, a solid
    when closed (surface_shape). Tolerance: `length` in document units, or `tolerance` as a
    fraction of the bounding-box diagonal of the control points; the object's Tolerance property
    is the length. mode "bspline" (default): one B-spline face per merged SDK surface
    (cagekit_limit_surfaces_*, max_level); "patches": one Bezier face per patch of
    cagekit_limit_patches_create (max_depth). Its properties record the mode, the options and the
    SDK's figures. One undo step; nothing changes on an error."""
    if mode not in MODES:
        raise WorkbenchError("mode must be one of %s, not %r" % (", ".join(MODES), mode))
    arrays, options, length = surface_request(cage_obj, tolerance, mode, max_level, max_depth, length)
    result = surface_shape(arrays, samples=0, progress=progress, **options)
    return apply_surface(cage_obj, result, arrays, length, max_level, max_depth, doc)


def sew_tolerance_for(control_points, info):
    """Sewing tolerance (model units): neighbouring patches may differ by the sum of their errors
    (an approximated patch beside an exact one, or the quadtree's T-junctions), so 2.5 x the
    largest error, plus 1e-9 of the diagonal for the rounding of exact ones."""
    return 2.5 * float(info.max_error) + 1e-9 * max(float(info.bbox_diagonal), 1e-300)


def export_step(obj_or_shape, path):
    """Writes the shape of a limit-surface object (or a cage: its limit surface is made first
    with the default options) or a Part.Shape as STEP. Atomic: a temporary file next to `path`
    is renamed over it, so a failure leaves no partial file. Returns the path."""
    if isinstance(obj_or_shape, Part.Shape):
        shape = obj_or_shape
    elif is_cage(obj_or_shape):
        shape = (surface_of(obj_or_shape) or limit_surface(obj_or_shape)).Shape
    elif is_limit_surface(obj_or_shape):
        shape = obj_or_shape.Shape
    else:
        raise WorkbenchError("select a CageKit cage or limit surface to export, not %r"
                             % getattr(obj_or_shape, "Label", obj_or_shape))
    if shape.isNull() or not shape.Faces:
        raise WorkbenchError("nothing to export: the shape has no faces")
    path = os.path.abspath(path)
    folder = os.path.dirname(path)
    if not os.path.isdir(folder):
        raise WorkbenchError("folder %s does not exist" % folder)
    fd, tmp = tempfile.mkstemp(prefix=".cagekit-", suffix=".step", dir=folder)
    os.close(fd)
    try:
        shape.exportStep(tmp)
        if os.path.getsize(tmp) == 0:
            raise WorkbenchError("FreeCAD wrote an empty STEP file")
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)
    FreeCAD.Console.PrintMessage("CageKit: wrote %s (%d faces)\n" % (path, len(shape.Faces)))
    return path


def insert(filename, docname):
    """FreeCAD's importer entry (File > Import, registered by Init.py for Draco .drc files)."""
    try:
        doc = FreeCAD.getDocument(docname)
    except Exception:
        doc = FreeCAD.newDocument(docname)
    return run_reported(import_scan, filename, doc, report=_gui_report())


def open(filename):  # noqa: A001  (FreeCAD's importer interface)
    """FreeCAD's importer entry (File > Open): a new document with the scan."""
    name = os.path.splitext(os.path.basename(filename))[0] or "Scan"
    doc = FreeCAD.newDocument(name)
    return run_reported(import_scan, filename, doc, report=_gui_report())


def _gui_report():
    if not FreeCAD.GuiUp:
        return None
    try:
        import CageKitGui
        return CageKitGui.show_error
    except Exception:
        return None
