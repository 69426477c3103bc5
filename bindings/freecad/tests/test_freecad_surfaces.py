# SPDX-License-Identifier: GPL-3.0-or-later
"""The limit surface as merged B-spline faces in FreeCAD (ctest freecad.surfaces, label freecad):

    freecadcmd bindings/freecad/tests/test_freecad_surfaces.py

freecadcmd 0.20 passes no arguments to a script, so it reads the environment: CAGEKIT_LIBRARY (the
built libcagekit), CAGEKIT_FREECAD_WHEEL (1: the installed workbench and wheel, see WHEEL), CAGEKIT_TEST_TOLERANCE (1e-3), CAGEKIT_TEST_OUT (scratch folder; default a
temporary one). ctest adds the test only when freecadcmd is found (bindings/CMakeLists.txt).

The cages are made here, so the test needs no shared files and stays small (seconds):
- closed: the unit cube with a 3 x 3 grid of quads per side, one top corner quad split into two
  triangles (6 ptex faces beside quads: T-junctions), the bottom's border edges creases; regular
  faces (exact surfaces), extraordinary corners (approximated ones);
- open: the same cube without its top side (a boundary loop).
Checks (mode "bspline", CageKitTools.surface_shape): one face per SDK surface (== ptex faces), the
default knot removal (fewer control points, surfaces moved by at most a tenth of the tolerance), and
without it each Part.BSplineSurface equal to the SDK's surface (knots, multiplicities, pole
orientation), the
shared borders identical, faces with vertices at the T-junctions; closed cage -> one closed shell
-> a valid solid of positive volume; one STEP round trip (same face count, one valid solid, each
face found again, every sampled limit-surface point within tolerance x diagonal + the sewing
tolerance of its face); open cage -> a valid open shell, no solid; mode "patches" (one Bezier face
per SDK patch) -> a valid solid too; limit_surface() on a cage object in both modes (its
properties); bad options -> messages. Exit code 1 on any failure (freecadcmd itself exits 0 after an
uncaught exception, so everything runs inside try).
"""
import os
import sys
import tempfile
import time
import traceback

import FreeCAD
import Part

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", "..", ".."))
TOLERANCE = float(os.environ.get("CAGEKIT_TEST_TOLERANCE", "1e-3"))
# CAGEKIT_FREECAD_WHEEL=1: the workbench installed in FREECAD_USER_HOME's Mod folder and cagekit from
# the wheel in its AdditionalPythonPackages (ctest freecad.wheel), instead of the source tree.
WHEEL = os.environ.get("CAGEKIT_FREECAD_WHEEL") == "1"

failures = []


def check(cond, what):
    print(("ok    " if cond else "FAIL  ") + what, flush=True)
    if not cond:
        failures.append(what)


CUBE = ((0, 0, 0), (1, 0, 0), (0, 1, 0), (1, 1, 0), (0, 0, 1), (1, 0, 1), (0, 1, 1), (1, 1, 1))
CUBE_SIDES = ((0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5))  # outward; 1: top


def grid_cube_cage(cagekit, np, n=3, open_top=False):
    """(cagekit.Cage, ptex face count): the unit cube, n x n quads per side (outward); the top
    side's first quad split into two triangles, or the top left out; the bottom's border creased."""
    index, points, faces = {}, [], []

    def vertex(p):
        key = tuple(int(round(c * n)) for c in p)
        if key not in index:
            index[key] = len(points)
            points.append(p)
        return index[key]

    for side, quad in enumerate(CUBE_SIDES):
        if open_top and side == 1:
            continue
        a, b, c, d = (np.array(CUBE[k], dtype=np.float64) for k in quad)
        grid = [[vertex((1 - s) * (1 - t) * a + s * (1 - t) * b + s * t * c + (1 - s) * t * d)
                 for t in np.linspace(0, 1, n + 1)] for s in np.linspace(0, 1, n + 1)]
        for i in range(n):
            for j in range(n):
                q = [grid[i][j], grid[i + 1][j], grid[i + 1][j + 1], grid[i][j + 1]]
                if side == 1 and i == 0 and j == 0:
                    faces += [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]
                else:
                    faces.append(q)
    pos = np.array(points)
    edges = {tuple(sorted((f[k], f[(k + 1) % len(f)]))) for f in faces for k in range(len(f))}
    creases = [e for e in sorted(edges) if pos[e[0], 2] == 0 and pos[e[1], 2] == 0 and any(
        pos[e[0], axis] == pos[e[1], axis] and pos[e[0], axis] in (0.0, 1.0) for axis in (0, 1))]
    sizes = np.array([len(f) for f in faces], dtype=np.uint32)
    flat = np.array([v for f in faces for v in f], dtype=np.uint32)
    cage = cagekit.Cage.from_arrays(pos, (sizes, flat), creases=np.array(creases, dtype=np.uint32))
    return cage, int(sum(1 if len(f) == 4 else len(f) for f in faces)), len(creases)


def main(out_dir):
    t_start = time.time()
    if WHEEL:
        # The workbench as the Addon Manager installs it (Mod/CageKit, no package inside) and the
        # cagekit wheel pip-installed into <user data>/AdditionalPythonPackages, which FreeCAD puts
        # on sys.path at start-up: nothing from the source or build tree.
        for var in ("CAGEKIT_LIBRARY", "PYTHONPATH"):
            check(var not in os.environ, "%s is unset" % var)
        packages = os.path.realpath(os.path.join(FreeCAD.getUserAppDataDir(), "AdditionalPythonPackages"))
        mod = os.path.realpath(os.path.join(FreeCAD.getUserAppDataDir(), "Mod", "CageKit"))
        check(packages in [os.path.realpath(p) for p in sys.path],
              "FreeCAD put %s on sys.path" % packages)
        import CageKitTools as tools
        check(os.path.realpath(tools.__file__).startswith(mod + os.sep),
              "CageKitTools imported from the installed workbench (%s)" % tools.__file__)
        cagekit = tools.sdk()
        check(os.path.realpath(cagekit.__file__).startswith(packages + os.sep),
              "cagekit imported from the installed wheel (%s)" % cagekit.__file__)
        check(os.path.realpath(cagekit.library_path).startswith(packages + os.sep),
              "libcagekit loaded from the installed wheel (%s)" % cagekit.library_path)
    else:
        sys.path[:0] = [os.path.join(ROOT, "bindings", "freecad", "CageKit"), os.path.join(ROOT, "bindings", "python")]
        import CageKitTools as tools
        cagekit = tools.sdk()
    import numpy as np
    print("FreeCAD %s, cagekit %s at %s" % (".".join(FreeCAD.Version()[:3]), cagekit.version(), cagekit.library_path))

    # --- the conversion of one knot vector ---------------------------------------------------------
    check(tools.knots_and_mults([0, 0, 0, 0, 0.25, 0.5, 0.5, 1, 1, 1, 1]) == ([0.0, 0.25, 0.5, 1.0], [4, 1, 2, 4]),
          "knots_and_mults: a full clamped vector -> distinct knots and multiplicities")

    # --- closed cage, mode bspline, one STEP round trip --------------------------------------------
    cage, ptex, crease_count = grid_cube_cage(cagekit, np)
    step = os.path.join(out_dir, "cube.step")
    r = tools.surface_shape(cage, tolerance=TOLERANCE, step=step)
    info, diag = r["info"], r["bbox_diagonal"]
    s = r["seconds"]
    print("closed cage: %d faces (%d ptex faces, %d creases): %d surfaces (%d exact, %d approximated), max error "
          "%.2e of the diagonal, max normal jump %.3f deg; seconds: limit %.2f, faces %.2f, sew %.2f, solid %.2f, "
          "STEP %.2f, total %.2f" % (cage.info().faces, ptex, crease_count, info.surface_count, info.exact_count,
                                     info.approximated_count, info.max_error_rel, info.max_normal_jump_deg,
                                     s["limit"], s["faces"], s["sew"], s["solid"], s["step"], s["total"]))
    check(r["mode"] == "bspline" and len(r["faces"]) == len(r["surfaces"]) == info.surface_count
          == info.ptex_face_count == ptex, "one face per SDK surface: %d == ptex faces %d" % (len(r["faces"]), ptex))
    check(info.exact_count > 0 and info.approximated_count > 0 and info.over_tolerance_count == 0
          and info.max_error_rel <= TOLERANCE, "exact and approximated surfaces, none over the tolerance (max %.2e)"
          % info.max_error_rel)
    g = np.linspace(0.0, 1.0, 5)
    uv = np.stack(np.meshgrid(g, g, indexing="ij"), axis=-1).reshape(-1, 2)

    def largest_gap(result):
        worst = 0.0
        for part, sdk_surface in zip(result["surfaces"], result["sdk_surfaces"]):
            mine = np.array([tuple(part.value(float(u), float(v))) for u, v in uv])
            worst = max(worst, float(np.linalg.norm(mine - sdk_surface.evaluate(uv), axis=1).max()))
        return worst

    # Knot removal (the default: a tenth of the tolerance) moves surfaces by at most that much.
    removal, counts = r["knot_removal"], r["counts"]
    worst = largest_gap(r)
    check(removal == 0.1 * TOLERANCE and counts["control_points"] < counts["control_points_before"]
          and 0 < r["max_knot_removal_deviation_rel"] <= removal and worst <= (removal + 1e-12) * diag
          and r["sew_tolerance"] >= 2.5 * removal * diag,
          "knot removal by default (%.0e of the diagonal): %d of %d control points left, surfaces moved by at most "
          "%.1e measured on 33 x 33 grids, %.1e at 25 (u, v) against cagekit's evaluate; sewing tolerance %.1e"
          % (removal, counts["control_points"], counts["control_points_before"], r["max_knot_removal_deviation_rel"],
             worst / diag, r["sew_tolerance"] / diag))
    z = tools.bspline_faces(cage, tolerance=TOLERANCE, samples=0, knot_removal=0)
    worst = largest_gap(z)
    check(worst <= 1e-12 * diag and z["counts"]["control_points"] == counts["control_points_before"]
          and z["max_knot_removal_deviation_rel"] == 0.0
          and all(p.UDegree == 3 and p.VDegree == 3 and not p.isURational() for p in z["surfaces"]),
          "knot_removal=0: each Part.BSplineSurface equals its SDK surface at 25 (u, v) (%.1e of the diagonal)"
          % (worst / diag))
    try:
        tools.bspline_faces(cage, tolerance=TOLERANCE, samples=0, knot_removal=-1.0)
        refused = ""
    except tools.WorkbenchError as e:
        refused = str(e)
    check("knot removal" in refused, "knot_removal=-1 refused: %r" % refused)
    check(r["border_gap"] <= 1e-12 * diag, "shared borders identical (largest gap %.1e of the diagonal; sewing "
          "tolerance %.1e)" % (r["border_gap"] / diag, r["sew_tolerance"] / diag))
    split = [len(f.Edges) for f in r["faces"] if len(f.Edges) > 4]
    check(len(split) >= 2, "%d faces beside the triangles' ptex faces have vertices at the T-junctions "
          "(edges %s)" % (len(split), sorted(set(split))))
    shape = r["shape"]
    check(r["closed"] and shape.ShapeType == "Solid" and r["valid"] and shape.isValid() and shape.Volume > 0
          and len(shape.Faces) == ptex and len(shape.Shells) == 1 and shape.Shells[0].isClosed(),
          "closed cage -> one closed shell -> a valid solid (volume %.4f, %d faces)" % (shape.Volume, len(shape.Faces)))
    check(os.path.isfile(step) and r["step_bytes"] == os.path.getsize(step) > 0,
          "STEP written (%d bytes)" % r["step_bytes"])
    rt = tools.step_round_trip(step, r)
    check(rt["faces"] == ptex and rt["solids"] == 1 and rt["closed"] and rt["valid"],
          "STEP read back: %d faces, %d solid, closed, valid" % (rt["faces"], rt["solids"]))
    check(rt["matched"] and rt["centre_gap"] <= 1e-9 * diag,
          "each face found again in the STEP file (surface centres %.1e of the diagonal apart)" % (rt["centre_gap"] / diag))
    k, points = r["samples"]
    check(rt["within"] and len(k) >= 200 and rt["max_distance"] <= TOLERANCE * diag + r["sew_tolerance"],
          "%d limit-surface points (cagekit Surface.evaluate; %d at corners) within %.1e of the diagonal of their "
          "re-imported face (distToShape: max %.2e)" % (len(k), len(k) // 8, rt["bound"] / diag,
                                                       rt["max_distance"] / diag))
    exact = np.array([r["sdk_surfaces"][int(i)].exact for i in k])
    on_exact = np.array([r["surfaces"][int(i)].value(float(u), float(v)) for i, (u, v) in
                         zip(k[exact], tools._sample_uv(len(k), len(r["surfaces"]), 11)[1][exact])])
    gap_exact = float(np.linalg.norm(on_exact.reshape(-1, 3) - points[exact], axis=1).max()) if exact.any() else 0.0
    check(exact.any() and gap_exact <= 1e-10 * diag,
          "exact surfaces: %d sampled points are the limit surface (%.1e of the diagonal)" % (int(exact.sum()),
                                                                                              gap_exact / diag))

    # --- mode patches on the same cage --------------------------------------------------------------------
    p = tools.surface_shape(cage, tolerance=TOLERANCE, mode="patches")
    with cagekit.LimitPatches(cage, tolerance=TOLERANCE) as patches:
        patch_count = patches.info.patch_count
    check(p["mode"] == "patches" and len(p["shape"].Faces) == patch_count > len(r["faces"]) and p["closed"]
          and p["valid"] and p["shape"].ShapeType == "Solid",
          "mode patches: %d Bezier faces (one per SDK patch) -> a valid solid (%.2f s)"
          % (len(p["shape"].Faces), p["seconds"]["total"]))

    # --- open cage -------------------------------------------------------------------------------------
    open_cage, open_ptex, _ = grid_cube_cage(cagekit, np, open_top=True)
    o = tools.surface_shape(open_cage, tolerance=TOLERANCE)
    boundary = sum(side.kind == cagekit.BorderKind.BOUNDARY for sdk_surface in o["sdk_surfaces"]
                   for side in sdk_surface.sides)
    check(len(o["faces"]) == open_ptex and boundary == 12, "open cage: %d faces, %d sides on the boundary"
          % (len(o["faces"]), boundary))
    check(not o["closed"] and o["shape"].ShapeType == "Shell" and not o["shape"].isClosed() and o["valid"]
          and not o["shape"].Solids and len(o["shape"].Faces) == open_ptex,
          "open cage -> a valid open shell of %d faces, no solid" % len(o["shape"].Faces))
    open_cage.close()

    # --- the workbench's object, both modes; bad options ------------------------------------------------
    doc = FreeCAD.newDocument("CageKitSurfaces")
    cage_obj = tools.new_cage_object(doc, "cube_cage", tools.cage_data(cage))
    obj = tools.limit_surface(cage_obj, tolerance=TOLERANCE)
    check(obj.Mode == "bspline" and obj.PatchCount == ptex == len(obj.Shape.Faces) and obj.Closed and obj.Valid
          and obj.Shape.ShapeType == "Solid" and obj.MaxLevel == 5 and obj.Seconds > 0
          and abs(obj.MaxNormalJumpDeg - info.max_normal_jump_deg) < 1e-12,
          "limit_surface(cage object): mode %s by default, %d faces, closed valid solid (%.2f s)"
          % (obj.Mode, obj.PatchCount, obj.Seconds))
    again = tools.limit_surface(cage_obj, tolerance=TOLERANCE, mode="patches")
    check(again is obj and obj.Mode == "patches" and obj.PatchCount == patch_count == len(obj.Shape.Faces)
          and obj.Closed and obj.Valid, "limit_surface(mode='patches') remakes it: %d faces" % obj.PatchCount)
    messages = []
    for what, words, kwargs in (("an unknown mode", ["mode", "bspline", "patches"], {"mode": "ptex"}),
                                ("max_level 8", ["max_level"], {"max_level": 8}),
                                ("a tolerance of 0", ["tolerance"], {"tolerance": 0.0})):
        n = len(messages)
        out = tools.run_reported(tools.limit_surface, cage_obj, report=messages.append, **kwargs)
        text = messages[n] if len(messages) > n else ""
        check(out is None and text.startswith("CageKit") and all(w in text for w in words) and obj.Mode == "patches",
              "%s -> %r, the surface unchanged" % (what, text))
    FreeCAD.closeDocument(doc.Name)
    cage.close()
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
