# SPDX-License-Identifier: GPL-3.0-or-later
"""The add-on's UI path in Blender with its GUI (ctest blender.modal, label blender):

    xvfb-run -a blender --factory-startup --enable-event-simulate --python test_blender_modal.py

CAGEKIT_LIBRARY names the built libcagekit; the add-on comes from the source tree. Unlike
`blender -b`, the GUI runs modal handlers and bpy.app.timers: the test is a generator stepped by a
timer, operators are invoked ('INVOKE_DEFAULT') in the 3D view's context, and Esc / right-click
are injected with Window.event_simulate (which needs --enable-event-simulate). Meshes are small
and generated (a torus of 2304 triangles). Checks:

- a modal Scan to Cage runs on a worker thread (timer callbacks run while it works) to the end,
  makes the cage and pushes an undo step: undo removes the cage, redo brings it back;
- Esc during Scan to Cage and right-click during Fit (both held mid-way by the operators'
  TEST_HOLD_FRACTION hook) cancel within 0.5 s and leave the scene unchanged (objects, vertices);
- simplify, quad and anisotropic each make a cage through the UI path (no fallback);
- a ring of edges marked sharp on the smooth torus becomes cage creases on that ring, for each
  method; without the marks the cage has no creases;
- bind (modal) and a cage edit move the scan for each method's cage, unbind stops it, and undo of a
  bind ends the binding.
The exit code is 1 when a check fails (os._exit from the timer).
"""
import os
import sys
import time
import traceback

import bpy
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", "..", ".."))
sys.path[:0] = [os.path.join(ROOT, "bindings", "blender"), os.path.join(ROOT, "bindings", "python")]
import addon_utils  # noqa: E402

failures = []
T0 = time.time()


def check(cond, what):
    print(("ok    " if cond else "FAIL  ") + what, flush=True)
    if not cond:
        failures.append(what)


def torus(nu=48, nv=24, R=1.0, r=0.4):
    u = np.linspace(0, 2 * np.pi, nu, endpoint=False)
    v = np.linspace(0, 2 * np.pi, nv, endpoint=False)
    U, V = np.meshgrid(u, v, indexing='ij')
    P = np.stack([(R + r * np.cos(V)) * np.cos(U), (R + r * np.cos(V)) * np.sin(U), r * np.sin(V)], -1).reshape(-1, 3)
    F = []
    for i in range(nu):
        for j in range(nv):
            a, b, c, d = i * nv + j, ((i + 1) % nu) * nv + j, ((i + 1) % nu) * nv + (j + 1) % nv, i * nv + (j + 1) % nv
            F += [[a, b, c], [a, c, d]]
    ring = [(i * nv, ((i + 1) % nu) * nv) for i in range(nu)]   # the outer equator (v = 0)
    return P, F, ring


def make_scan(name, mark_ring):
    P, F, ring = torus()
    me = bpy.data.meshes.new(name)
    me.from_pydata(P.tolist(), [], F)
    me.update()
    if mark_ring:
        keys = {tuple(sorted(e)) for e in ring}
        flags = [tuple(sorted(e.vertices)) in keys for e in me.edges]
        me.edges.foreach_set("use_edge_sharp", flags)
    obj = bpy.data.objects.new(name, me)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def positions(obj):
    me = obj.data
    co = np.empty(len(me.vertices) * 3, dtype=np.float32)
    me.vertices.foreach_get("co", co)
    return co.reshape(-1, 3).astype(np.float64)


def crease_edges(obj):
    me = obj.data
    c = np.empty(len(me.edges), dtype=np.float32)
    me.edges.foreach_get("crease", c)
    ev = np.empty(len(me.edges) * 2, dtype=np.int32)
    me.edges.foreach_get("vertices", ev)
    return ev.reshape(-1, 2)[c > 0.99]


def snapshot():
    return {o.name: (o.type, positions(o).copy() if o.type == 'MESH' else None) for o in bpy.data.objects}


def same_scene(a, b):
    if set(a) != set(b):
        return False
    return all(a[k][0] == b[k][0] and (a[k][1] is None or (a[k][1].shape == b[k][1].shape and
                                                          np.array_equal(a[k][1], b[k][1]))) for k in a)


def ui_override():
    win = bpy.context.window_manager.windows[0]
    area = next(a for a in win.screen.areas if a.type == 'VIEW_3D')
    region = next(r for r in area.regions if r.type == 'WINDOW')
    return win, dict(window=win, screen=win.screen, area=area, region=region)


def activate(*objs):
    for o in bpy.context.view_layer.objects:
        o.select_set(False)
    for o in objs:
        o.select_set(True)
    bpy.context.view_layer.objects.active = objs[0]


def invoke(op, **kw):
    _, ov = ui_override()
    with bpy.context.temp_override(**ov):
        return op('INVOKE_DEFAULT', **kw)


def undo_push(message):
    _, ov = ui_override()
    with bpy.context.temp_override(**ov):
        bpy.ops.ed.undo_push(message=message)


def undo(redo=False):
    _, ov = ui_override()
    with bpy.context.temp_override(**ov):
        return bpy.ops.ed.redo() if redo else bpy.ops.ed.undo()


METHOD_OPTS = dict(faces=100, passes=2, quad_edge_length=0.08, quad_regions=20, aniso_tolerance=0.004,
                   fallback_to_simplify=False)


def guide_edges():
    """marked_sharp_edges: sharp marks, seams and face-set borders, each only when asked for."""
    from cagekit_blender import operators
    obj = make_scan("guides", mark_ring=True)
    me = obj.data
    me.edges[5].use_seam = True
    attr = me.attributes.new("sculpt_face_set", 'INT', 'FACE')
    ids = np.array([1 if p.center.y >= 0 else 2 for p in me.polygons], dtype=np.int32)
    attr.data.foreach_set("value", ids)
    sharp = operators.marked_sharp_edges(obj)
    seams = operators.marked_sharp_edges(obj, sharp=False, seams=True)
    sets = operators.marked_sharp_edges(obj, sharp=False, face_sets=True)
    co = positions(obj)
    ends = co[sets.ravel()] if len(sets) else np.zeros((0, 3))
    centers = np.array([p.center[:] for p in me.polygons])
    check(len(sharp) == 48 and len(seams) == 1 and len(operators.marked_sharp_edges(obj, sharp=False)) == 0,
          "guides: 48 edges marked sharp, 1 seam, nothing when neither is asked for")
    faces_of = {}        # edges between a face with y >= 0 and one with y < 0, counted independently
    for i, p in enumerate(me.polygons):
        for k in p.edge_keys:
            faces_of.setdefault(k, []).append(i)
    border = sum(1 for f in faces_of.values()
                 if len(f) == 2 and (centers[f[0], 1] >= 0) != (centers[f[1], 1] >= 0))
    check(len(sets) == border > 0 and np.all(np.abs(ends[:, 1]) < 0.2),
          "guides: the %d face-set border edges (attribute sculpt_face_set) are found, all near y = 0 (%d)"
          % (border, len(sets)))
    bpy.data.objects.remove(obj)


def cancel_held_job(event):
    """Generator step of steps(): waits until the running job is held mid-way (TEST_HOLD_FRACTION),
    presses and releases `event` in the window, then waits until the job has ended."""
    from cagekit_blender import operators
    t = time.time()
    while not (operators.running_jobs and operators.running_jobs[0]._held) and time.time() - t < 60:
        yield
    check(bool(operators.running_jobs), "the job is held mid-way (stage %r, %.2f)" % (
        operators.running_jobs[0].stage if operators.running_jobs else None,
        operators.running_jobs[0].fraction if operators.running_jobs else -1))
    win, _ = ui_override()
    win.event_simulate(type=event, value='PRESS')
    win.event_simulate(type=event, value='RELEASE')
    t = time.time()
    while operators.running_jobs and time.time() - t < 30:
        yield


def steps():
    from cagekit_blender import handlers, operators
    guide_edges()
    # ---- a modal job to the end, with undo and redo ----------------------------------------------
    scan = make_scan("torus", mark_ring=False)
    activate(scan)
    undo_push("test setup")
    yield
    # Blender's first seconds in the GUI (shader compilation, first draws; slow with software GL)
    # keep the main loop busy: wait until the timer runs every ~20 ms for 0.5 s (at most 60 s).
    t, last, calm = time.time(), time.time(), 0
    while calm < 25 and time.time() - t < 60:
        yield
        now = time.time()
        calm = calm + 1 if now - last < 0.1 else 0
        last = now
    print("    Blender settled after %.1f s" % (time.time() - t), flush=True)
    ticks = [0]
    result = invoke(bpy.ops.cagekit.scan_to_cage, method='SIMPLIFY', **METHOD_OPTS)
    check(result == {'RUNNING_MODAL'}, "Scan to Cage invoked from the 3D view goes modal (%s)" % result)
    check(len(operators.running_jobs) == 1, "one running job listed")
    t = time.time()
    while operators.running_jobs and time.time() - t < 120:
        ticks[0] += 1     # this generator is stepped by a bpy.app.timers callback
        yield
    job = operators.last_job
    check(job is not None and job["state"] == 'FINISHED', "the modal job finished (%s)" % job)
    print("    steps (s): %s; %d timer callbacks during the job" % (
        {k: round(v, 4) for k, v in job["timings"].items()}, ticks[0]), flush=True)
    check(ticks[0] >= 3, "bpy.app.timers callbacks ran while the job worked (%d)" % ticks[0])
    cage = bpy.data.objects.get("torus_cage")
    check(cage is not None and len(cage.data.polygons) > 0 and cage.get("cagekit_method") == "simplify",
          "the cage object torus_cage was made by simplify")
    check("undo_push" in job["timings"], "the finish step pushed an undo step")
    undo()
    yield
    check(bpy.data.objects.get("torus_cage") is None and bpy.data.objects.get("torus") is not None,
          "undo removes the cage, the scan stays")
    undo(redo=True)
    yield
    check(bpy.data.objects.get("torus_cage") is not None, "redo brings the cage back")

    # ---- Esc cancels Scan to Cage mid-way ------------------------------------------------------
    activate(bpy.data.objects["torus"])
    before = snapshot()
    operators.TEST_HOLD_FRACTION = 0.2
    try:
        result = invoke(bpy.ops.cagekit.scan_to_cage, method='SIMPLIFY', **METHOD_OPTS)
        check(result == {'RUNNING_MODAL'}, "second Scan to Cage goes modal")
        yield from cancel_held_job('ESC')
    finally:
        operators.TEST_HOLD_FRACTION = None
    job = operators.last_job
    check(job["state"] == 'CANCELLED', "Esc cancelled Scan to Cage (%s)" % job)
    check(job["cancel_latency"] is not None and job["cancel_latency"] < 0.5,
          "the SDK stopped %.3f s after the cancel (limit 0.5 s)" % (job["cancel_latency"] or -1))
    check(job["modal_calls_after_cancel"] == 0,
          "the operator ended in the handler call that saw Esc, not after Blender's next redraw (%s)"
          % job["modal_calls_after_cancel"])
    check(same_scene(before, snapshot()), "the scene is as it was (objects and vertices)")

    # ---- right-click cancels Fit mid-way --------------------------------------------------------
    cage = bpy.data.objects["torus_cage"]
    activate(cage, bpy.data.objects["torus"])
    before = snapshot()
    operators.TEST_HOLD_FRACTION = 0.0
    try:
        result = invoke(bpy.ops.cagekit.fit, passes=3)
        check(result == {'RUNNING_MODAL'}, "Fit goes modal")
        yield from cancel_held_job('RIGHTMOUSE')
    finally:
        operators.TEST_HOLD_FRACTION = None
    job = operators.last_job
    check(job["operator"] == "cagekit.fit" and job["state"] == 'CANCELLED'
          and (job["cancel_latency"] or 1e9) < 0.5,
          "right-click cancelled Fit within 0.5 s (%s)" % job)
    check(job["modal_calls_after_cancel"] == 0, "Fit ended in the handler call that saw the right-click")
    check(same_scene(before, snapshot()), "the cage's vertices are as they were")

    # ---- a modal Fit to the end; undo restores the vertices -------------------------------------
    cage = bpy.data.objects["torus_cage"]
    activate(cage, bpy.data.objects["torus"])
    rest = positions(cage)
    invoke(bpy.ops.cagekit.fit, passes=2)
    while operators.running_jobs:
        yield
    moved = positions(bpy.data.objects["torus_cage"])
    check(operators.last_job["state"] == 'FINISHED' and not np.array_equal(moved, rest),
          "a modal Fit moved the cage's vertices")
    undo()
    yield
    check(np.array_equal(positions(bpy.data.objects["torus_cage"]), rest), "undo of Fit restores them")

    # ---- the three methods, with and without marked sharp edges; bind, edit, unbind ---------------
    plain_creases = None
    for method in ('SIMPLIFY', 'QUAD', 'ANISOTROPIC'):
        name = "ring_" + method.lower()
        scan = make_scan(name, mark_ring=True)
        activate(scan)
        undo_push("test " + name)
        yield
        t = time.time()
        result = invoke(bpy.ops.cagekit.scan_to_cage, method=method, use_sharp_edges=True, **METHOD_OPTS)
        while operators.running_jobs:
            yield
        job = operators.last_job
        cage = bpy.data.objects.get(name + "_cage")
        check(result == {'RUNNING_MODAL'} and job["state"] == 'FINISHED' and cage is not None
              and cage.get("cagekit_method") == method.lower(),
              "%s through the UI path: %s, %s (%.1f s)" % (method.lower(), job["state"], job["message"],
                                                          time.time() - t))
        if cage is None:
            continue
        edges = crease_edges(cage)
        q = positions(cage)[edges.ravel()] if len(edges) else np.zeros((0, 3))
        rho = np.hypot(q[:, 0], q[:, 1]) if len(q) else np.zeros(0)
        check(len(edges) > 0 and cage.get("cagekit_sharp_edges") == 48 and np.all(np.abs(q[:, 2]) < 0.2)
              and np.all(rho > 1.25),
              "%s: the 48 marked edges (outer equator) became %d cage creases, all on it (|z| <= %.3f, "
              "radius >= %.3f)" % (method.lower(), len(edges), np.abs(q[:, 2]).max() if len(q) else -1,
                                   rho.min() if len(rho) else -1))
        if method == 'SIMPLIFY':
            plain = make_scan("plain", mark_ring=False)
            activate(plain)
            invoke(bpy.ops.cagekit.scan_to_cage, method=method, use_sharp_edges=True, **METHOD_OPTS)
            while operators.running_jobs:
                yield
            plain_creases = len(crease_edges(bpy.data.objects["plain_cage"]))
            check(plain_creases == 0, "without marks the torus cage has no creases (%d)" % plain_creases)

        # live editing: bind (modal), move a cage vertex, the scan follows; unbind stops it
        scan = bpy.data.objects[name]
        activate(cage, scan)
        result = invoke(bpy.ops.cagekit.bind)
        while operators.running_jobs:
            yield
        check(result == {'RUNNING_MODAL'} and operators.last_job["state"] == 'FINISHED'
              and name in handlers.bindings(), "%s: bind (modal) made a live binding" % method.lower())
        before = positions(scan)
        cpos = positions(cage)
        cpos[0] += (0.0, 0.0, 0.1)
        cage.data.vertices.foreach_set("co", cpos.astype(np.float32).ravel())
        cage.data.update()
        bpy.context.view_layer.update()
        yield
        after = positions(scan)
        moved = int(np.count_nonzero(np.any(np.abs(after - before) > 1e-7, axis=1)))
        check(0 < moved < len(after), "%s: a cage edit moved %d of %d scan vertices" % (method.lower(), moved,
                                                                                        len(after)))
        activate(cage)
        _, ov = ui_override()
        with bpy.context.temp_override(**ov):
            r = bpy.ops.cagekit.unbind()
        cpos[0] += (0.0, 0.0, 0.1)
        cage.data.vertices.foreach_set("co", cpos.astype(np.float32).ravel())
        cage.data.update()
        bpy.context.view_layer.update()
        yield
        check(r == {'FINISHED'} and name not in handlers.bindings() and np.array_equal(positions(scan), after),
              "%s: after unbind a cage edit leaves the scan alone" % method.lower())

    # ---- undo of a bind ends the binding -----------------------------------------------------
    scan, cage = bpy.data.objects["ring_simplify"], bpy.data.objects["ring_simplify_cage"]
    activate(cage, scan)
    undo_push("before bind")
    invoke(bpy.ops.cagekit.bind)
    while operators.running_jobs:
        yield
    bound = "ring_simplify" in handlers.bindings()
    undo()
    yield
    check(bound and "ring_simplify" not in handlers.bindings(), "undo of bind ends the binding")


def main():
    mod = addon_utils.enable("cagekit_blender", default_set=True, handle_error=None)
    check(mod is not None and hasattr(bpy.ops.cagekit, "scan_to_cage"), "add-on enabled from the source tree")
    check(not bpy.app.background and "event_simulate" in bpy.types.Window.bl_rna.functions,
          "Blender runs with its GUI and --enable-event-simulate")
    gen = steps()
    deadline = time.time() + 240

    def tick():
        try:
            if time.time() > deadline:
                raise TimeoutError("the test ran past 240 s")
            next(gen)
            return 0.02
        except StopIteration:
            code = 1 if failures else 0
        except BaseException:
            traceback.print_exc()
            failures.append("exception")
            code = 1
        print("%d failure(s) in %.1f s" % (len(failures), time.time() - T0), flush=True)
        for f in failures:
            print("  FAILED: " + f, flush=True)
        sys.stdout.flush()
        os._exit(code)
    bpy.app.timers.register(tick, first_interval=0.5)


main()
