# SPDX-License-Identifier: GPL-3.0-or-later
"""QuadriFlow (Blender's bpy.ops.object.quadriflow_remesh) on one mesh, for tests/bench/bench_remesh.

    blender -b --factory-startup --python tests/bench/quadriflow_blender.py -- IN.obj OUT.obj TARGET_FACES [SCALE] [RUNS]

Settings as in ../shared/spec/peer-measurements.md section 3: mode='FACES', seed=0, no symmetry,
no sharp or boundary preservation, no normal smoothing, no paint mask. The input is imported
without axis conversion (forward Y, up Z); when SCALE != 1 its vertices are multiplied by SCALE
before the operator runs (QuadriFlow refuses edges shorter than 1e-4 in absolute units, e.g. on
the generated 1.1M-triangle bunny) and the output is divided by SCALE again when written, so OUT
is in the units of IN. Only the operator call is timed (time.perf_counter, and process CPU
time), on RUNS fresh copies of the imported mesh (default 1); the last copy's result is written
to OUT.obj (vertices and polygons, nothing else). Timing and status go to OUT.obj.json:
{"seconds": [...], "cpu_seconds": [...], "median_seconds", "median_cpu_seconds", "faces",
"vertices", "scale", "status", "message", "blender", "import_mib" (VmRSS before the first call),
"peak_mib" (largest VmHWM of a call, Blender and the imported mesh included; the peak is reset
through /proc/self/clear_refs before each call)}. Exit code 0 also when QuadriFlow fails (status "failed", no OUT.obj); 2 on
bad arguments or an input that does not import.
"""
import json
import os
import statistics
import sys
import time

import bpy
import mathutils


def arguments():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    if len(argv) < 3:
        print(__doc__, file=sys.stderr)
        sys.exit(2)
    scale = float(argv[3]) if len(argv) > 3 else 1.0
    runs = int(argv[4]) if len(argv) > 4 else 1
    return argv[0], argv[1], int(argv[2]), scale, max(1, runs)


def import_obj(path):
    before = set(bpy.data.objects)
    if hasattr(bpy.ops.wm, "obj_import"):  # Blender >= 3.3: the C++ importer (fast on 1M triangles)
        bpy.ops.wm.obj_import(filepath=path, forward_axis="Y", up_axis="Z")
    else:
        bpy.ops.import_scene.obj(filepath=path, axis_forward="Y", axis_up="Z", split_mode="OFF")
    new = [o for o in bpy.data.objects if o not in before and o.type == "MESH"]
    if len(new) != 1:
        print("quadriflow_blender: %s imported as %d mesh objects" % (path, len(new)), file=sys.stderr)
        sys.exit(2)
    return new[0]


def status_mib(field):
    """A "Field:  1234 kB" line of /proc/self/status in MiB (Linux); None elsewhere."""
    try:
        with open("/proc/self/status") as status:
            for line in status:
                if line.startswith(field + ":"):
                    return int(line.split()[1]) / 1024.0
    except OSError:
        pass
    return None


def reset_peak():
    try:
        with open("/proc/self/clear_refs", "w") as f:
            f.write("5")
    except OSError:
        pass


def fresh_copy(source):
    obj = source.copy()
    obj.data = source.data.copy()
    bpy.context.scene.collection.objects.link(obj)
    for o in bpy.context.view_layer.objects:
        o.select_set(False)
    obj.select_set(True)
    bpy.context.view_layer.objects.active = obj
    return obj


def write_obj(mesh, path, scale):
    inv = 1.0 / scale
    with open(path, "w") as out:
        out.write("# QuadriFlow (Blender %s) output\n" % bpy.app.version_string)
        for v in mesh.vertices:
            out.write("v %.9g %.9g %.9g\n" % (v.co.x * inv, v.co.y * inv, v.co.z * inv))
        for p in mesh.polygons:
            out.write("f " + " ".join(str(i + 1) for i in p.vertices) + "\n")


def main():
    in_path, out_path, target, scale, runs = arguments()
    for obj in list(bpy.data.objects):  # the factory scene's cube, camera and light
        bpy.data.objects.remove(obj, do_unlink=True)
    source = import_obj(in_path)
    if scale != 1.0:
        source.data.transform(mathutils.Matrix.Scale(scale, 4))
    source.hide_set(True)
    in_polygons = len(source.data.polygons)
    in_vertices = [tuple(v.co) for v in source.data.vertices] if in_polygons < 200000 else None

    report = {"seconds": [], "cpu_seconds": [], "scale": scale, "target_faces": target, "status": "ok",
              "message": "", "blender": bpy.app.version_string, "input_faces": in_polygons}
    result = None
    for _ in range(runs):
        obj = fresh_copy(source)
        if "import_mib" not in report:
            report["import_mib"] = status_mib("VmRSS")
        reset_peak()
        t0, c0 = time.perf_counter(), time.process_time()
        try:
            ret = bpy.ops.object.quadriflow_remesh(
                mode="FACES", target_faces=target, seed=0, use_mesh_symmetry=False, use_preserve_sharp=False,
                use_preserve_boundary=False, smooth_normals=False, preserve_paint_mask=False)
        except RuntimeError as e:  # operator errors are raised in background mode
            ret, report["message"] = {"CANCELLED"}, str(e).strip()
        report["seconds"].append(time.perf_counter() - t0)
        report["cpu_seconds"].append(time.process_time() - c0)
        peak = status_mib("VmHWM")
        if peak is not None:
            report["peak_mib"] = max(report.get("peak_mib", 0.0), peak)
        unchanged = len(obj.data.polygons) == in_polygons and (
            in_vertices is None or len(obj.data.vertices) != len(in_vertices) or
            all(tuple(v.co) == p for v, p in zip(obj.data.vertices, in_vertices)))
        if "FINISHED" not in ret or unchanged:
            report["status"] = "failed"
            if not report["message"]:
                report["message"] = "operator returned %s%s" % (sorted(ret), ", mesh unchanged" if unchanged else "")
            break
        result = obj
    report["median_seconds"] = statistics.median(report["seconds"])
    report["median_cpu_seconds"] = statistics.median(report["cpu_seconds"])
    if result is not None and report["status"] == "ok":
        write_obj(result.data, out_path, scale)
        report["faces"] = len(result.data.polygons)
        report["vertices"] = len(result.data.vertices)
    elif os.path.exists(out_path):
        os.remove(out_path)
    with open(out_path + ".json", "w") as out:
        json.dump(report, out)
    print("quadriflow_blender: " + json.dumps(report))


main()
