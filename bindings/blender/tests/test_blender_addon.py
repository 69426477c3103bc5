# SPDX-License-Identifier: GPL-3.0-or-later
"""The CageKit add-on inside Blender (ctest blender.addon, label blender):

    blender -b --factory-startup --python-exit-code 1 --python test_blender_addon.py -- \
        [--cli build/samples/cli/cagekit] [--mesh fandisk.obj] [--faces 200] [--passes 3]

CAGEKIT_LIBRARY names the built libcagekit. The add-on is enabled from the source tree
(bindings/blender and bindings/python on sys.path). The scan is fandisk from ../shared/meshes
(or CAGEKIT_SHARED_MESHES, or --mesh), else a generated noisy block (the output says which).
Checks: scan_to_cage makes an object with the same cage as the Python binding (faces, creases
as Blender creases 1.0), a Subdivision Surface modifier whose evaluated mesh equals `cagekit
subdivide` of the same cage within 1e-5 of the bounding-box diagonal, fit gives the binding's
fit, a cage edit moves the bound scan's vertices (as the deformer computes) and unbind stops
that, bad input gives an operator error and Blender goes on.
"""
import argparse
import os
import subprocess
import sys
import tempfile
import time

import bpy
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", "..", ".."))
argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
ap = argparse.ArgumentParser()
ap.add_argument("--cli", default=os.path.join(ROOT, "build", "samples", "cli", "cagekit"))
ap.add_argument("--mesh", default=None)
ap.add_argument("--faces", type=int, default=200)
ap.add_argument("--passes", type=int, default=3)
ap.add_argument("--levels", type=int, default=2)
ap.add_argument("--zip", default=None,
                help="install this add-on zip (into $BLENDER_USER_SCRIPTS, which must be set) instead of "
                     "using the source tree; the library is then the zip's own copy")
args = ap.parse_args(argv)

import addon_utils  # noqa: E402

failures = []


def check(cond, what):
    print(("ok    " if cond else "FAIL  ") + what, flush=True)
    if not cond:
        failures.append(what)


def link(obj):
    bpy.context.scene.collection.objects.link(obj)
    return obj


def activate(*objs):
    for o in bpy.context.view_layer.objects:
        o.select_set(False)
    for o in objs:
        o.select_set(True)
    bpy.context.view_layer.objects.active = objs[0]


def positions(obj_or_mesh):
    me = obj_or_mesh.data if isinstance(obj_or_mesh, bpy.types.Object) else obj_or_mesh
    co = np.empty(len(me.vertices) * 3, dtype=np.float32)
    me.vertices.foreach_get("co", co)
    return co.reshape(-1, 3).astype(np.float64)


def generated_scan():
    """A noisy tessellated block with a chamfer-free box shape (42 x 30 x 18 grid)."""
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
    rng = np.random.default_rng(7)
    pos += rng.normal(scale=2e-3, size=pos.shape)
    return pos, np.array(faces)


# --- the add-on --------------------------------------------------------------------------------
t0 = time.time()
if args.zip:
    scripts = os.environ.get("BLENDER_USER_SCRIPTS")
    if not scripts:
        sys.exit("test_blender_addon: --zip needs BLENDER_USER_SCRIPTS set to a scratch folder")
    os.environ.pop("CAGEKIT_LIBRARY", None)
    sys.path.insert(0, os.path.join(ROOT, "packaging", "tests"))
    import load_proof  # noqa: E402  (/proc/self/maps: where each bundled library was loaded from)
    mapped_before = load_proof.mapped()
    result = bpy.ops.preferences.addon_install(filepath=os.path.abspath(args.zip), overwrite=True)
    check(result == {'FINISHED'}, "addon_install of %s into %s" % (args.zip, scripts))
    mod = addon_utils.enable("cagekit_blender", default_set=True, handle_error=None)
    check(mod is not None and os.path.realpath(mod.__file__).startswith(os.path.realpath(scripts)),
          "add-on cagekit_blender enabled from the installed zip (%s)" % (mod and mod.__file__))
    from cagekit_blender import _sdk  # noqa: E402
    cagekit = _sdk.sdk()
    check(os.path.realpath(cagekit.library_path).startswith(os.path.realpath(scripts)),
          "the bundled libcagekit is the one loaded (%s)" % cagekit.library_path)
    cagekit.Cage(cagekit.Mesh.from_bytes(load_proof.CUBE_OBJ, "obj")).subdivide(1).close()  # OpenSubdiv in use
    proof = load_proof.check(os.path.dirname(cagekit.__file__), mapped_before, host="Blender")
    check(not proof, "every bundled library of the zip is loaded from the zip or shared with Blender "
                     "(loaded by Blender before the add-on) %s" % proof)
else:
    sys.path[:0] = [os.path.join(ROOT, "bindings", "blender"), os.path.join(ROOT, "bindings", "python")]
    import cagekit  # noqa: E402
    mod = addon_utils.enable("cagekit_blender", default_set=True, handle_error=None)
    check(mod is not None and hasattr(bpy.ops.cagekit, "scan_to_cage"),
          "add-on cagekit_blender enabled from the source tree")
print("blender %s, python %s, cagekit %s at %s" % (bpy.app.version_string, sys.version.split()[0],
                                                  cagekit.version(), cagekit.library_path))

# --- the scan ------------------------------------------------------------------------------------
shared = os.environ.get("CAGEKIT_SHARED_MESHES") or os.path.join(ROOT, "..", "shared", "meshes")
mesh_path = args.mesh or os.path.join(shared, "fandisk.obj")
if os.path.isfile(mesh_path):
    ref_scan = cagekit.Mesh.read(mesh_path)
    print("scan: real mesh %s (%d vertices, %d faces)" % (mesh_path, *ref_scan.counts()[:2]))
    scan_pos, scan_faces = ref_scan.positions, np.array(ref_scan.faces)  # (F, 3): the scan is triangles
else:
    print("scan: %s absent; using a generated noisy block" % mesh_path)
    scan_pos, scan_faces = generated_scan()
    ref_scan = cagekit.Mesh.from_arrays(scan_pos, scan_faces)
scan_me = bpy.data.meshes.new("scan")
scan_me.from_pydata(scan_pos.tolist(), [], np.asarray(scan_faces).tolist())
scan_me.update()
scan = link(bpy.data.objects.new("scan", scan_me))
check(np.allclose(positions(scan), scan_pos, atol=1e-5 * max(1.0, np.abs(scan_pos).max())),
      "scan object made with the mesh's vertices in order")
diag = float(np.linalg.norm(scan_pos.max(0) - scan_pos.min(0)))
# Blender stores float32 coordinates: the reference runs on exactly what the add-on reads
ref_scan = cagekit.Mesh.from_arrays(positions(scan), scan_faces)

# --- scan_to_cage --------------------------------------------------------------------------------
activate(scan)
from cagekit_blender import operators as addon_operators  # noqa: E402
progress_calls = []
plain_call = addon_operators._Progress.__call__


def counting_call(self, stage, fraction):
    progress_calls.append((stage, self.lo + (self.hi - self.lo) * fraction, self.wm is not None))
    return plain_call(self, stage, fraction)


addon_operators._Progress.__call__ = counting_call
t = time.time()
result = bpy.ops.cagekit.scan_to_cage(faces=args.faces, passes=args.passes, levels=args.levels)
print("scan_to_cage: %s in %.2f s" % (result, time.time() - t))
addon_operators._Progress.__call__ = plain_call
stages = sorted({c[0] for c in progress_calls if c[0]})
check(len(stages) >= 2 and max(c[1] for c in progress_calls) > 0.99 and all(c[2] for c in progress_calls),
      "progress: %d SDK callbacks (stages %s) drive the window manager's progress to %.2f"
      % (len(progress_calls), ", ".join(stages), max(c[1] for c in progress_calls) if progress_calls else 0))
check(result == {'FINISHED'}, "scan_to_cage finished")
cage = bpy.data.objects.get("scan_cage")
check(cage is not None and cage.type == 'MESH', "cage object 'scan_cage' exists")



def reference_cage(target):
    # The binding's steps at the target the journey used (it tries finer targets while the limit
    # strays or self-intersects more than the scan): level, cage.
    with cagekit.Hierarchy(ref_scan) as h:
        level = h.set_level(faces=target)
        faces = h.level_info(level).faces
        coarser = h.level_info(level + 1).faces if level + 1 < h.level_count else None
        built, built_report = h.build_cage(crease_angle_degrees=30.0)
    return built, built_report, faces, coarser


target = int(cage.get("cagekit_target_faces", args.faces))
ref_cage0, ref_report, level_faces, coarser = reference_cage(target)
ref_cage, ref_fit = cagekit.fit(ref_cage0, ref_scan, max_passes=args.passes,
                                fairing=float(cage.get("cagekit_fit_fairing", 0.0)))
check(target >= args.faces and level_faces <= target and (coarser is None or coarser < level_faces),
      "simplified level: %d faces for %d asked (target used %d; the finest level with at most that many)"
      % (level_faces, args.faces, target))
check(cage.get("cagekit_level_faces") == level_faces, "cage records the level's face count %d" % level_faces)
cage_faces = len(cage.data.polygons)
check(cage_faces == ref_cage.info().faces,
      "cage face count %d == the binding's quad-dominant cage of that level (%d; %d quads)"
      % (cage_faces, ref_cage.info().faces, ref_report.quads))
err = np.abs(positions(cage) - ref_cage.positions).max() / diag
check(err < 1e-6, "cage vertices == the binding's fitted cage (%.1e of the diagonal)" % err)

# creases: Blender crease 1.0 on exactly the cage's infinitely sharp edges
me = cage.data
ev = np.empty(len(me.edges) * 2, dtype=np.int32)
me.edges.foreach_get("vertices", ev)
ev = np.sort(ev.reshape(-1, 2), axis=1)
if "crease" in bpy.types.MeshEdge.bl_rna.properties:
    crease = np.empty(len(me.edges), dtype=np.float32)
    me.edges.foreach_get("crease", crease)
else:
    crease = np.zeros(len(me.edges), dtype=np.float32)
    me.attributes["crease_edge"].data.foreach_get("value", crease)
ref_pairs, ref_sharp = ref_cage.creases
blender_creased = {tuple(e) for e in ev[crease > 0].tolist()}
ref_creased = {tuple(sorted(p)) for p in ref_pairs.tolist()}
check(len(ref_creased) > 0 and blender_creased == ref_creased and np.all(crease[crease > 0] == 1.0),
      "creases set: %d edges at crease 1.0 == the cage's %d sharp tags" % (len(blender_creased), len(ref_creased)))

# --- Blender's Subdivision Surface modifier == cagekit subdivide ------------------------------------
mods = [m for m in cage.modifiers if m.type == 'SUBSURF']
check(len(mods) == 1 and mods[0].use_creases and mods[0].subdivision_type == 'CATMULL_CLARK'
      and mods[0].levels == args.levels,
      "Subdivision Surface modifier: Catmull-Clark, creases on, %d levels, limit surface %s, boundary %s"
      % (args.levels, mods[0].use_limit_surface if mods else None, mods[0].boundary_smooth if mods else None))
depsgraph = bpy.context.evaluated_depsgraph_get()
evaluated = cage.evaluated_get(depsgraph)
emesh = evaluated.to_mesh()
blender_pts = positions(emesh)
blender_faces = len(emesh.polygons)
evaluated.to_mesh_clear()

tmp = tempfile.mkdtemp(prefix="cagekit_blender_")
# the cage as Blender holds it (vertices, polygons, creases read back) through the add-on's reader
from cagekit_blender import meshio  # noqa: E402
with meshio.cage_from_object(cage) as exported:
    exported.write(os.path.join(tmp, "cage.obj"))
cli_out = os.path.join(tmp, "subdivided.obj")
if os.path.isfile(args.cli):
    proc = subprocess.run([args.cli, "subdivide", os.path.join(tmp, "cage.obj"), cli_out, "--levels",
                           str(args.levels), "--quiet"], capture_output=True, text=True)
    check(proc.returncode == 0, "cagekit subdivide ran (%s)" % (proc.stderr.strip() or "rc 0"))
    ck_sub = cagekit.Mesh.read(cli_out)
    how = "cagekit subdivide (CLI %s)" % args.cli
else:
    ck_sub = cagekit.Cage.read(os.path.join(tmp, "cage.obj")).subdivide(args.levels).mesh()
    how = "Cage.subdivide (CLI %s absent)" % args.cli
ck_pts = ck_sub.positions
from mathutils.kdtree import KDTree  # noqa: E402


def one_way(a, b):
    tree = KDTree(len(b))
    for i, p in enumerate(b):
        tree.insert(p, i)
    tree.balance()
    return max(tree.find(p)[2] for p in a)


match = max(one_way(blender_pts, ck_pts), one_way(ck_pts, blender_pts)) / diag
check(len(blender_pts) == len(ck_pts) and blender_faces == ck_sub.counts()[1],
      "level %d: Blender %d vertices / %d faces, %s %d / %d"
      % (args.levels, len(blender_pts), blender_faces, how, len(ck_pts), ck_sub.counts()[1]))
check(match <= 1e-5, "SUBDIVISION MATCH: Blender's modifier vs %s: max distance %.2e of the bbox diagonal "
      "(limit 1e-5)" % (how, match))

# an open mesh: boundary edges stay uncreased in Blender (boundaries are sharp in OpenSubdiv anyway;
# a crease there would make Blender pin valence-2 boundary vertices) and the surfaces still agree
n = 24
gx, gy = np.meshgrid(np.linspace(0, 2, n + 1), np.linspace(0, 1.5, n + 1), indexing="ij")
gpos = np.stack([gx.ravel(), gy.ravel(), 0.2 * np.sin(3 * gx.ravel()) * np.cos(2 * gy.ravel())], axis=1)
gid = np.arange((n + 1) ** 2).reshape(n + 1, n + 1)
gfaces = np.concatenate([np.stack([gid[:-1, :-1].ravel(), gid[1:, :-1].ravel(), gid[1:, 1:].ravel()], 1),
                         np.stack([gid[:-1, :-1].ravel(), gid[1:, 1:].ravel(), gid[:-1, 1:].ravel()], 1)])
gme = bpy.data.meshes.new("sheet")
gme.from_pydata(gpos.tolist(), [], gfaces.tolist())
gme.update()
sheet = link(bpy.data.objects.new("sheet", gme))
activate(sheet)
result = bpy.ops.cagekit.scan_to_cage(faces=20, passes=1, levels=args.levels)
sheet_cage = bpy.context.active_object
dg = bpy.context.evaluated_depsgraph_get()
ev_obj = sheet_cage.evaluated_get(dg)
ev_mesh = ev_obj.to_mesh()
sheet_pts = positions(ev_mesh)
ev_obj.to_mesh_clear()
with meshio.cage_from_object(sheet_cage) as c:
    ck_sheet = c.subdivide(args.levels).positions
counts = meshio.edge_face_counts(sheet_cage.data)
boundary_creases = int(np.count_nonzero(meshio.edge_creases(sheet_cage.data)[counts < 2]))
sheet_diag = float(np.linalg.norm(gpos.max(0) - gpos.min(0)))
sheet_match = max(one_way(sheet_pts, ck_sheet), one_way(ck_sheet, sheet_pts)) / sheet_diag
check(result == {'FINISHED'} and int(np.count_nonzero(counts < 2)) > 0 and boundary_creases == 0
      and len(sheet_pts) == len(ck_sheet) and sheet_match <= 1e-5,
      "open sheet (%d boundary edges, none creased): Blender's modifier vs Cage.subdivide %.2e of the diagonal"
      % (int(np.count_nonzero(counts < 2)), sheet_match))

# --- fit -----------------------------------------------------------------------------------------
activate(scan)
result = bpy.ops.cagekit.scan_to_cage(faces=args.faces, passes=0, levels=1)
raw = bpy.context.active_object
check(result == {'FINISHED'} and raw.name == "scan_cage.001", "scan_to_cage without fitting made %s" % raw.name)
raw_cage0 = reference_cage(int(raw.get("cagekit_target_faces", args.faces)))[0]
err0 = np.abs(positions(raw) - raw_cage0.positions).max() / diag
activate(raw, scan)
result = bpy.ops.cagekit.fit(passes=args.passes)
ref_pos = cagekit.fit(raw_cage0, ref_scan, max_passes=args.passes)[0].positions
err = np.abs(positions(raw) - ref_pos).max() / diag
check(result == {'FINISHED'} and err0 < 1e-6 and err < 1e-6,
      "cagekit.fit moves the unfitted cage onto the binding's fit (%.1e of the diagonal; rms %.2e)"
      % (err, raw.get("cagekit_fit_rms_rel", -1)))

# --- bind: a cage edit moves the scan ---------------------------------------------------------------
activate(cage)
result = bpy.ops.cagekit.bind(scan="scan")
check(result == {'FINISHED'}, "bind finished")
from cagekit_blender import handlers  # noqa: E402
entry = handlers.bindings().get("scan")
check(entry is not None and entry.cage_name == "scan_cage", "live binding scan -> scan_cage registered")
rest = positions(scan)
cpos = positions(cage)
k = int(np.argmax(cpos[:, 2]))
offset = np.array([0.0, 0.0, 0.05 * diag])
edited = cpos.copy()
edited[k] += offset
t = time.time()
cage.data.vertices.foreach_set("co", edited.astype(np.float32).ravel())
cage.data.update()
bpy.context.view_layer.update()      # the depsgraph update runs the handler
dt = time.time() - t
moved = np.linalg.norm(positions(scan) - rest, axis=1)
check(entry.updates >= 1 and moved.max() > 1e-3 * diag,
      "cage vertex %d moved by %.3g: %d scan vertices moved (max %.3g, %d deformer run(s), %.3f s)"
      % (k, offset[2], int(np.count_nonzero(moved > 1e-9 * diag)), moved.max(), entry.updates, dt))
# expected: rest + D(edited) - D(original), from the Python binding directly
bound_cpos = cpos.astype(np.float32).astype(np.float64)  # what Blender stores
ref_bind = cagekit.bind(cagekit.Cage.from_arrays(bound_cpos, ref_cage.face_arrays(), creases=ref_pairs), ref_scan)
deformer = cagekit.CpuDeformer(ref_bind)
d0, _ = deformer.deform(bound_cpos, normals=False)
d1, _ = deformer.deform(edited.astype(np.float32).astype(np.float64), normals=False)
expect = rest + (d1 - d0)
err = np.abs(positions(scan) - expect).max() / diag
check(err < 1e-5, "scan == rest + deform(edited cage) - deform(cage) (%.1e of the diagonal)" % err)
check(np.count_nonzero(moved > 1e-9 * diag) < len(moved), "the edit is local: far vertices stay")

# the same in edit mode: the handler reads the cage's edit-mode vertices while they are dragged
import bmesh  # noqa: E402
activate(cage)
bpy.ops.object.mode_set(mode='EDIT')
runs, before = entry.updates, positions(scan)
bm = bmesh.from_edit_mesh(cage.data)
bm.verts.ensure_lookup_table()
bm.verts[k].co.z -= 0.5 * offset[2]
bmesh.update_edit_mesh(cage.data)
bpy.context.view_layer.update()
moved_edit = np.linalg.norm(positions(scan) - before, axis=1).max()
bpy.ops.object.mode_set(mode='OBJECT')
check(entry.updates == runs + 1 and moved_edit > 1e-3 * diag,
      "edit mode: dragging cage vertex %d moves the scan live (max %.3g, error %s)"
      % (k, moved_edit, entry.last_error))

result = bpy.ops.cagekit.unbind()
check(result == {'FINISHED'} and not handlers.bindings()
      and handlers.on_depsgraph_update not in bpy.app.handlers.depsgraph_update_post,
      "unbind ends the binding and removes the handler")
after = positions(scan)
edited[k] -= 2 * offset
cage.data.vertices.foreach_set("co", edited.astype(np.float32).ravel())
cage.data.update()
bpy.context.view_layer.update()
check(np.array_equal(positions(scan), after), "after unbind a cage edit leaves the scan alone")

# --- bad input: operator errors, Blender goes on ----------------------------------------------------
def expect_error(what, words, **op_args):
    try:
        r = bpy.ops.cagekit.scan_to_cage(**op_args)
        check(False, "%s: operator error expected, got %s" % (what, r))
    except RuntimeError as e:  # bpy.ops raises RuntimeError carrying the ERROR report
        text = str(e).strip().replace("\n", " ")
        check(all(w in text for w in words), "%s -> operator error %r" % (what, text))


pts = bpy.data.meshes.new("points")
pts.from_pydata([(0, 0, 0), (1, 0, 0), (0, 1, 0)], [], [])
activate(link(bpy.data.objects.new("points", pts)))
expect_error("a mesh with no faces", ["CageKit", "no faces"])
fan = bpy.data.meshes.new("fin")  # three triangles on one edge: non-manifold, conditioned by the SDK
fan.from_pydata([(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1)], [], [(0, 1, 2), (1, 0, 3), (0, 1, 4)])
activate(link(bpy.data.objects.new("fin", fan)))
r = bpy.ops.cagekit.scan_to_cage(faces=60, passes=2)
fin_cage = bpy.data.objects.get("fin_cage")
check(r == {'FINISHED'} and fin_cage is not None and len(fin_cage.data.polygons) == 3,
      "a non-manifold mesh is conditioned (its edge split) and is its own 3-face cage: %s" % (r,))
nanm = bpy.data.meshes.new("nan")  # a NaN coordinate: refused by the SDK's validation
nanm.from_pydata([(float("nan"), 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)], [],
                 [(0, 2, 1), (0, 1, 3), (1, 2, 3), (0, 3, 2)])
activate(link(bpy.data.objects.new("nan", nanm)))
expect_error("a mesh with a NaN vertex", ["CageKit"])
degenerate = bpy.data.meshes.new("degenerate")  # every face has zero area
degenerate.from_pydata([(0, 0, 0), (1, 0, 0), (2, 0, 0), (3, 0, 0)], [], [(0, 1, 2), (1, 2, 3), (0, 1, 3)])
activate(link(bpy.data.objects.new("degenerate", degenerate)))
expect_error("a mesh of zero-area faces", ["CageKit"])
activate(cage)
try:
    bpy.ops.cagekit.fit(scan="points")
    check(False, "fit to a scan without faces: error expected")
except RuntimeError as e:
    check("no faces" in str(e), "fit to a scan without faces -> operator error %r" % str(e).strip())
activate(scan)
result = bpy.ops.cagekit.scan_to_cage(faces=args.faces, passes=0, levels=1)
check(result == {'FINISHED'}, "Blender and the add-on still work after the errors")

addon_utils.disable("cagekit_blender", default_set=True)
check(not hasattr(bpy.types, "CAGEKIT_OT_scan_to_cage"), "add-on disabled cleanly")
print("total %.1f s; %d failure(s)" % (time.time() - t0, len(failures)))
if failures:
    print("FAILED:\n  " + "\n  ".join(failures))
    sys.exit(1)
