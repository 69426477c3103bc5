# SPDX-License-Identifier: GPL-3.0-or-later
"""The CageKit workbench's functions inside FreeCAD, headless (ctests freecad.workbench and
freecad.addon, label freecad):

    freecadcmd bindings/freecad/tests/test_freecad_workbench.py

freecadcmd 0.20 passes no arguments to a script, so it reads the environment:
  CAGEKIT_LIBRARY         the built libcagekit (source-tree mode)
  CAGEKIT_FREECAD_ADDON=1 use the addon installed in FreeCAD's Mod folder (FREECAD_USER_HOME/Mod/
                          CageKit, made by make_addon.cmake) with its bundled library instead
  CAGEKIT_SHARED_MESHES   folder of fandisk.obj (default ../shared/meshes); CAGEKIT_TEST_MESH a mesh
                          file, or "generated" for the generated block even where fandisk is present
  CAGEKIT_TEST_FACES (200), CAGEKIT_TEST_PASSES (3), CAGEKIT_TEST_TOLERANCE (1e-3),
  CAGEKIT_TEST_SAMPLES (400), CAGEKIT_TEST_SHELL_SAMPLES (1: of those, against the whole shell),
  CAGEKIT_TEST_OUT (scratch folder; default a temporary one)
The scan is fandisk, else a generated noisy block (the output says which). Checks: the cage's face
count and vertices equal the Python binding's (same level, same fit), the limit surface in mode
"patches" has one face per SDK patch and is a closed valid solid for a closed cage, the STEP file
re-imports with one face per patch, limit-surface points (cagekit Surface.evaluate) lie within tolerance x diagonal of
the re-imported faces and shell, and bad input (a corrupt mesh file, an empty mesh, a NaN vertex, a
NaN control point, bad options, a missing folder) gives an error message, leaves nothing behind,
and FreeCAD goes on. Exit code 1 on any failure (freecadcmd itself exits 0 after an uncaught
exception, so everything runs inside try).
"""
import os
import sys
import tempfile
import time
import traceback

import FreeCAD
import Mesh
import Part

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", "..", ".."))
ADDON = os.environ.get("CAGEKIT_FREECAD_ADDON") == "1"
FACES = int(os.environ.get("CAGEKIT_TEST_FACES", "200"))
PASSES = int(os.environ.get("CAGEKIT_TEST_PASSES", "3"))
TOLERANCE = float(os.environ.get("CAGEKIT_TEST_TOLERANCE", "1e-3"))
SAMPLES = int(os.environ.get("CAGEKIT_TEST_SAMPLES", "400"))
# distToShape against fandisk's whole re-imported shell (8,654 faces) takes about a minute a point;
# against the point's own face, a fraction of a second.
SHELL_SAMPLES = int(os.environ.get("CAGEKIT_TEST_SHELL_SAMPLES", "1"))

failures = []


def check(cond, what):
    print(("ok    " if cond else "FAIL  ") + what, flush=True)
    if not cond:
        failures.append(what)


def generated_block():
    """A noisy tessellated 2 x 1.4 x 0.8 box (12 x 12 grid per side, welded, outward)."""
    import numpy as np
    n = 12
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
    pos = np.array(verts)
    pos += np.random.default_rng(7).normal(scale=2e-3, size=pos.shape)
    return pos, np.array(faces)


def mesh_object(doc, name, points, triangles):
    obj = doc.addObject("Mesh::Feature", name)
    obj.Mesh = Mesh.Mesh(([FreeCAD.Vector(*map(float, p)) for p in points], [tuple(map(int, f)) for f in triangles]))
    return obj


def main(out_dir):
    t_start = time.time()
    # --- the workbench and the SDK ---------------------------------------------------------------
    if ADDON:
        os.environ.pop("CAGEKIT_LIBRARY", None)
        mod = os.path.realpath(os.path.join(FreeCAD.getUserAppDataDir(), "Mod", "CageKit"))
        check("CageKitTools" in (FreeCAD.getImportType("drc") or []),
              "the addon's Init.py ran at start-up (Draco import registered: %s)" % FreeCAD.getImportType("drc"))
        import CageKitTools as tools
        check(os.path.realpath(tools.__file__).startswith(mod + os.sep),
              "CageKitTools imported from the installed addon (%s)" % tools.__file__)
        cagekit = tools.sdk()
        check(os.path.realpath(cagekit.library_path).startswith(mod + os.sep),
              "the bundled libcagekit is the one loaded (%s)" % cagekit.library_path)
    else:
        sys.path[:0] = [os.path.join(ROOT, "bindings", "freecad", "CageKit"), os.path.join(ROOT, "bindings", "python")]
        import CageKitTools as tools
        cagekit = tools.sdk()
    import numpy as np
    print("FreeCAD %s, python %s, numpy %s, cagekit %s at %s" % (
        ".".join(FreeCAD.Version()[:3]), sys.version.split()[0], np.__version__, cagekit.version(),
        cagekit.library_path), flush=True)
    doc = FreeCAD.newDocument("CageKitTest")

    # --- the scan -----------------------------------------------------------------------------------
    shared = os.environ.get("CAGEKIT_SHARED_MESHES") or os.path.join(ROOT, "..", "shared", "meshes")
    path = os.environ.get("CAGEKIT_TEST_MESH") or os.path.join(shared, "fandisk.obj")
    real = path != "generated" and os.path.isfile(path)
    if real:
        t = time.time()
        scan = tools.import_scan(path, doc)
        with cagekit.Mesh.read(path) as m:
            counts = m.counts()[:2]
        print("scan: real mesh %s (%d vertices, %d faces), imported in %.2f s" % (path, counts[0], counts[1],
                                                                                  time.time() - t))
        check((scan.Mesh.CountPoints, scan.Mesh.CountFacets) == counts,
              "import_scan: mesh object with the file's %d vertices and %d triangles" % counts)
    else:
        print("scan: %s" % ("the generated noisy block (CAGEKIT_TEST_MESH=generated)" if path == "generated"
                            else "%s absent; using a generated noisy block" % path))
        pos, tris = generated_block()
        scan = mesh_object(doc, "scan", pos, tris)
    scan_pos, scan_tris = tools.mesh_arrays(scan)
    diag_scan = float(np.linalg.norm(scan_pos.max(0) - scan_pos.min(0)))

    # --- scan -> cage -------------------------------------------------------------------------------
    t = time.time()
    cage_obj = tools.scan_to_cage(scan, faces=FACES)
    t_cage = time.time() - t
    check(cage_obj is not None and cage_obj in doc.Objects and cage_obj.Label == scan.Label + "_cage",
          "scan_to_cage made %r in %.2f s" % (cage_obj.Label, t_cage))
    ref_scan = cagekit.Mesh.from_arrays(scan_pos, scan_tris)
    # The journey may raise the target (finer levels while the limit strays or self-intersects
    # more than the scan): the reference is the binding's level at the target it used.
    target = int(cage_obj.TargetFaces)
    with cagekit.Hierarchy(ref_scan) as h:
        level = h.set_level(faces=target)
        level_faces = h.level_info(level).faces
        ref_cage0, ref_report = h.build_cage(crease_angle_degrees=30.0)
    check(target >= FACES and cage_obj.LevelFaces == level_faces and level_faces <= target and
          level_faces >= 0.75 * target,
          "simplified level: %d faces for %d asked (target used %d)" % (cage_obj.LevelFaces, FACES, target))
    data = tools.cage_arrays(cage_obj)
    ref = tools.cage_data(ref_cage0)
    check(len(data["sizes"]) == len(ref["sizes"]) and np.array_equal(data["flat"], ref["flat"]),
          "cage: %d faces (%d quads), the same as the Python binding's cage of that level"
          % (len(data["sizes"]), int(np.sum(data["sizes"] == 4))))
    check(np.array_equal(data["creases"], ref["creases"]) and len(data["creases"]) > 0,
          "cage: the binding's %d crease edges" % len(data["creases"]))
    unique_edges = {tuple(sorted(e)) for f in np.split(data["flat"], np.cumsum(data["sizes"])[:-1])
                    for e in zip(f, np.roll(f, -1))}
    check(len(cage_obj.Shape.Edges) == len(unique_edges), "cage shape: its %d edges" % len(unique_edges))

    # --- fit ----------------------------------------------------------------------------------------
    t = time.time()
    report = tools.fit_cage(cage_obj, passes=PASSES)
    t_fit = time.time() - t
    ref_cage, ref_fit = cagekit.fit(ref_cage0, ref_scan, max_passes=PASSES)
    fitted = tools.cage_arrays(cage_obj)["positions"]
    err = np.abs(fitted - ref_cage.positions).max() / diag_scan
    check(err < 1e-9 and report.final.rms_rel < report.initial.rms_rel,
          "fit_cage: %d passes in %.2f s, rms %.2e -> %.2e of the diagonal, vertices == the binding's fit (%.1e)"
          % (len(report.passes) - 1, t_fit, report.initial.rms_rel, report.final.rms_rel, err))
    check(cage_obj.FitPasses == len(report.passes) - 1 and abs(cage_obj.FitRmsRel - report.final.rms_rel) < 1e-15,
          "cage records FitPasses %d and FitRmsRel %.2e" % (cage_obj.FitPasses, cage_obj.FitRmsRel))

    # --- limit surface ------------------------------------------------------------------------------
    t = time.time()
    surface = tools.limit_surface(cage_obj, tolerance=TOLERANCE, mode="patches")
    t_surface = time.time() - t
    patches = cagekit.LimitPatches(ref_cage, tolerance=TOLERANCE)
    info = patches.info
    diag = info.bbox_diagonal
    closed_cage = ref_cage.info().boundary_edges == 0
    check(surface.PatchCount == info.patch_count and len(surface.Shape.Faces) == info.patch_count,
          "limit_surface in %.2f s: %d faces == the SDK's %d patches (%d exact, %d approximated, "
          "max error %.2e of the diagonal, %d over the tolerance)" % (
              t_surface, len(surface.Shape.Faces), info.patch_count, info.exact_count, info.approximated_count,
              info.max_error_rel, info.over_tolerance_count))
    check(info.max_error_rel <= TOLERANCE * (1 + 1e-9) and info.over_tolerance_count == 0,
          "reported max error %.2e <= tolerance %.0e" % (info.max_error_rel, TOLERANCE))
    shape = surface.Shape
    if closed_cage:
        check(surface.Closed and shape.ShapeType == "Solid" and shape.isValid() and shape.Volume > 0,
              "closed cage -> a valid closed solid (volume %.4g, sew tolerance %.1e of the diagonal)"
              % (shape.Volume, surface.SewTolerance / diag))
    else:
        check(len(shape.Shells) == 1, "open cage -> one shell")

    # --- STEP ---------------------------------------------------------------------------------------
    step = os.path.join(out_dir, "limit.step")
    t = time.time()
    tools.export_step(surface, step)
    t_step = time.time() - t
    check(os.path.isfile(step) and os.path.getsize(step) > 0,
          "export_step wrote %s (%d bytes) in %.2f s" % (step, os.path.getsize(step), t_step))
    t = time.time()
    back = Part.read(step)
    t_read = time.time() - t
    check(len(back.Faces) == info.patch_count,
          "STEP re-import (%.2f s): %d faces, one per SDK patch (%d)" % (t_read, len(back.Faces), info.patch_count))
    if closed_cage:
        check(len(back.Solids) == 1 and len(back.Shells) == 1 and back.Shells[0].isClosed() and back.isValid(),
              "STEP re-import: one valid solid bounded by one closed shell")
    faces = back.Faces
    shell = back.Shells[0] if back.Shells else Part.makeCompound(faces)

    # each re-imported face is one patch: matched by the centre of its surface, a bijection
    cp = patches.control_points
    n = len(cp)
    centres_sdk = patches.evaluate(np.arange(n), np.full((n, 2), 0.5))
    centres_step = np.array([tuple(f.Surface.value(0.5, 0.5)) for f in faces])
    match = np.empty(n, dtype=np.int64)   # patch -> STEP face
    gap = np.empty(n)
    for lo in range(0, n, 512):
        d = np.linalg.norm(centres_sdk[lo:lo + 512, None, :] - centres_step[None, :, :], axis=2)
        match[lo:lo + 512] = np.argmin(d, axis=1)
        gap[lo:lo + 512] = d[np.arange(len(d)), match[lo:lo + 512]]
    kinds = {(f.Surface.TypeId, f.Surface.UDegree, f.Surface.VDegree, f.Surface.NbUPoles, f.Surface.NbVPoles,
              tuple(f.Surface.bounds())) for f in faces}
    check(len(set(match.tolist())) == n and gap.max() < 1e-12 * diag
          and kinds == {("Part::GeomBSplineSurface", 3, 3, 4, 4, (0.0, 1.0, 0.0, 1.0))},
          "each STEP face is one SDK patch (centres %.1e of the diagonal apart), a bicubic B-spline with "
          "4 x 4 poles on [0, 1]^2" % gap.max())

    # limit-surface points (the SDK's evaluator, not the patches) against the re-imported faces
    rng = np.random.default_rng(11)
    k = rng.integers(0, n, SAMPLES)
    st = rng.random((SAMPLES, 2))
    st[:len(st) // 8] = np.round(st[:len(st) // 8])  # some patch corners, where neighbours meet
    ptex, uv = patches.ptex_locations(k, st)
    with ref_cage.surface() as evaluator:
        limit = evaluator.evaluate(ptex, uv).position
    step_faces = [faces[int(match[i])] for i in k]
    on_face = np.array([tuple(f.Surface.value(float(s), float(t))) for f, (s, t) in zip(step_faces, st)])
    pointwise = np.linalg.norm(on_face - limit, axis=1)
    errors = patches.errors
    exact = patches.exact
    slack = 1e-9 * diag
    ex = exact[k]
    # the SDK measures a patch's error on a 33 x 33 grid, not between the samples: 2x there
    check(np.all(pointwise <= 2.0 * errors[k] + slack) and pointwise.max() <= TOLERANCE * diag * 2.0 + slack,
          "%d limit points vs their STEP face at equal parameters: max %.2e of the diagonal (patch errors "
          "up to %.2e)" % (SAMPLES, pointwise.max() / diag, info.max_error_rel))
    if ex.any():
        check(pointwise[ex].max() <= 1e-10 * diag,
              "exact patches: %d points within %.1e of the diagonal" % (int(ex.sum()), pointwise[ex].max() / diag))
    t = time.time()
    to_face = np.array([f.distToShape(Part.Vertex(FreeCAD.Vector(*map(float, p))))[0]
                        for f, p in zip(step_faces, limit)])
    # the whole shell (points inside patches)
    inner = np.arange(len(st) // 8, len(st))[:SHELL_SAMPLES]
    m = len(inner)
    to_shell = np.array([shell.distToShape(Part.Vertex(FreeCAD.Vector(*map(float, p))))[0] for p in limit[inner]])
    t_dist = time.time() - t
    check(to_face.max() <= TOLERANCE * diag + slack and np.all(to_shell <= to_face[inner] + slack),
          "%d limit points -> the re-imported shape (distToShape, %.1f s): max %.2e of the diagonal <= %.0e "
          "(%d inside patches against the whole shell: max %.2e)" % (SAMPLES, t_dist, to_face.max() / diag, TOLERANCE,
                                                              m, to_shell.max() / diag))

    # --- bad input: an error message, nothing made, FreeCAD goes on ------------------------------------
    messages = []
    before = len(doc.Objects)

    def expect_error(what, words, action, *a, **kw):
        n = len(messages)
        count = len(doc.Objects)
        result = tools.run_reported(action, *a, report=messages.append, **kw)
        text = messages[n] if len(messages) > n else ""
        check(result is None and len(messages) == n + 1 and all(w.lower() in text.lower() for w in words)
              and len(doc.Objects) == count, "%s -> %r" % (what, text))

    bad_obj = os.path.join(out_dir, "corrupt.obj")
    with open(bad_obj, "w") as f:
        f.write("v 0 0 0\nv 1 0 0\nv 0 1 zero\nf 1 2 3\n")
    expect_error("a corrupt OBJ file", ["CageKit", "corrupt.obj", ":3"], tools.import_scan, bad_obj, doc)
    bad_drc = os.path.join(out_dir, "corrupt.drc")
    with open(bad_drc, "wb") as f:
        f.write(b"DRACO\x02\x02\x01\x01\x00\x00" + bytes(range(256)) * 4)
    expect_error("a corrupt Draco file", ["CageKit", "corrupt.drc"], tools.import_scan, bad_drc, doc)
    n = len(messages)
    result = tools.insert(bad_drc, doc.Name)  # FreeCAD's importer entry: reports, never raises
    check(result is None and len(messages) == n,
          "File > Import of the corrupt .drc returns quietly (error on the console)")
    empty = doc.addObject("Mesh::Feature", "empty")
    expect_error("an empty mesh", ["CageKit", "no faces"], tools.scan_to_cage, empty, faces=50)
    nan = mesh_object(doc, "nan", [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, float("nan"))],
                      [(0, 2, 1), (0, 1, 3), (1, 2, 3), (0, 3, 2)])
    expect_error("a NaN vertex", ["CageKit", "finite"], tools.scan_to_cage, nan, faces=2)
    fin = mesh_object(doc, "fin", [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1)],
                      [(0, 1, 2), (1, 0, 3), (0, 1, 4)])
    expect_error("a fin: 3 triangles on one edge (FreeCAD's Mesh keeps none of them)", ["CageKit"],
                 tools.scan_to_cage, fin, faces=2)
    expect_error("a tolerance of 0", ["CageKit", "tolerance"], tools.limit_surface, cage_obj, tolerance=0.0)
    expect_error("a NaN tolerance", ["CageKit", "tolerance"], tools.limit_surface, cage_obj, tolerance=float("nan"))
    expect_error("max_depth 13", ["CageKit", "max_depth"], tools.limit_surface, cage_obj, max_depth=13,
                 mode="patches")
    expect_error("an unknown mode", ["CageKit", "mode", "bspline", "patches"], tools.limit_surface, cage_obj,
                 mode="faces")
    expect_error("a mesh given as cage", ["CageKit", "not a CageKit cage"], tools.limit_surface, scan)
    points = list(cage_obj.ControlPoints)
    broken = list(points)
    broken[0] = FreeCAD.Vector(float("nan"), 0, 0)
    cage_obj.ControlPoints = broken
    expect_error("a NaN control point", ["CageKit"], tools.limit_surface, cage_obj)
    cage_obj.ControlPoints = points
    expect_error("a missing folder", ["CageKit", "does not exist"], tools.export_step, surface,
                 os.path.join(out_dir, "no", "such", "x.step"))
    check(not any(name.startswith(".cagekit-") for name in os.listdir(out_dir)), "no temporary STEP file left behind")
    doc.removeObject(empty.Name)
    doc.removeObject(nan.Name)
    doc.removeObject(fin.Name)
    check(len(doc.Objects) == before, "bad input added no objects")
    again = tools.limit_surface(cage_obj, tolerance=TOLERANCE, mode="patches")
    check(again is surface and again.PatchCount == info.patch_count,
          "FreeCAD and the workbench still work after the errors (the surface remade: %d patches)" % again.PatchCount)
    print("times: cage %.2f s, fit %.2f s, limit surface %.2f s, STEP write %.2f s, read %.2f s; total %.1f s"
          % (t_cage, t_fit, t_surface, t_step, t_read, time.time() - t_start))


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
