# SPDX-License-Identifier: GPL-3.0-or-later
"""The add-on's operators: cagekit.scan_to_cage, cagekit.fit, cagekit.bind, cagekit.unbind.

Long operators (scan_to_cage, fit, bind) are jobs in three steps:

  start   (main thread)   reads what the SDK needs out of Blender into numpy arrays and makes the
                          job's cagekit.Context (threads and memory budget from the preferences);
  work    (worker thread) the SDK calls only, on those arrays (no bpy: every SDK call releases the
                          GIL, so Blender's UI goes on while it runs);
  finish  (main thread)   the mesh hand-over (new object, moved vertices, a live binding), then an
                          explicit undo push `bpy.ops.ed.undo_push`, timed separately.

invoke() (a click in the UI) runs the work on a threading.Thread and goes modal: a window-manager
timer updates the progress bar and the status-bar text, Esc or right-click cancels through the
context (the progress callback returns False and Context.cancel() is called, so the SDK stops at
its next check) and nothing is changed in the scene. execute() (scripts, `blender -b`, which has
no event loop for modal operators) runs the same three steps synchronously.

The long operators have no 'REGISTER'/'UNDO' options, so Blender's redo panel never reruns a long
job behind the user's back; their options are set in the sidebar (the scene's CageKit settings,
copied into every option the caller did not set) and undo comes from the explicit push. Every SDK
failure becomes an operator error report and {'CANCELLED'}; nothing is made before the finish step.
"""
import math
import threading
import time

import bpy
import numpy as np
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, StringProperty

from . import handlers, meshio
from ._sdk import sdk

# --- test and benchmark hooks ----------------------------------------------------------------------
# TEST_HOLD_FRACTION: when set (a float), the worker's progress callback waits, once the job's
# progress reaches it, until the job is cancelled (at most 60 s): tests cancel a job "mid-way"
# deterministically on small meshes. last_job: the record of the latest finished, cancelled or
# failed job (operator, state, message, timings of the steps in seconds, cancel latency).
TEST_HOLD_FRACTION = None
last_job = None
running_jobs = []    # the jobs of modal operators now running (tests and the sidebar read it)
STATUS_INTERVAL = 0.5  # seconds between changes of the status-bar text of a running job
# After Esc or right-click the modal handler waits this long for the SDK to stop (it stops within
# about 0.35 s on a million-triangle scan), so the operator ends in the same call; otherwise it
# ended only at the next handler call, after Blender's next redraw (0.5 s and more with a large
# scan in the viewport). If the work is still running then, the operator goes on waiting modally.
CANCEL_WAIT = 0.5


def _active_mesh(context):
    """Operators that need an active mesh object (their poll)."""
    obj = context.active_object
    return obj is not None and obj.type == 'MESH'


def _cage_and_scan(context, cage_obj, scan_name):
    """The checked scan for the active cage object (by name, or found as _find_scan does)."""
    _check_mesh(cage_obj, "cage")
    scan = _find_scan(context, cage_obj, scan_name)
    _check_mesh(scan, "scan")
    if scan is cage_obj:
        raise ValueError("the scan and the cage are the same object")
    return scan


class _Progress:
    """Blender's progress bar (the window manager's; in background mode it prints nothing)
    driven by CageKit's progress callback on the main thread (execute()): stage `name` covers
    [lo, hi] of the bar."""

    def __init__(self, context):
        self.wm = getattr(context, "window_manager", None)
        self.lo, self.hi = 0.0, 1.0
        try:
            self.wm.progress_begin(0, 1000)
        except Exception:
            self.wm = None

    def stage(self, lo, hi):
        self.lo, self.hi = lo, hi
        self(None, 0.0)

    def __call__(self, _stage, fraction):
        if self.wm is not None:
            f = min(max(float(fraction), 0.0), 1.0)
            try:
                self.wm.progress_update(int(1000 * (self.lo + (self.hi - self.lo) * f)))
            except Exception:
                pass
        return None   # the job decides about cancelling

    def end(self):
        if self.wm is not None:
            try:
                self.wm.progress_end()
            except Exception:
                pass


def _message(e):
    return getattr(e, "message", None) or str(e) or type(e).__name__


def _fail(op, e):
    op.report({'ERROR'}, "CageKit: %s" % _message(e))
    return {'CANCELLED'}


def _relative(target, source):
    """Matrix taking `source` local coordinates into `target` local coordinates."""
    return target.matrix_world.inverted_safe() @ source.matrix_world


def _check_mesh(obj, what):
    if obj is None or obj.type != 'MESH':
        raise ValueError("the %s must be a mesh object" % what)
    if obj.mode == 'EDIT':
        obj.update_from_editmode()
    if len(obj.data.polygons) == 0:
        raise ValueError("%s %r has no faces" % (what, obj.name))


def _find_scan(context, cage, name):
    """The scan for a cage: the operator's `scan` name, else the cage's 'cagekit_scan' property,
    else the other selected mesh object."""
    if name:
        obj = bpy.data.objects.get(name)
        if obj is None:
            raise ValueError("no object named %r" % name)
        return obj
    name = cage.get("cagekit_scan")
    if name and bpy.data.objects.get(name) is not None:
        return bpy.data.objects[name]
    others = [o for o in context.selected_objects if o is not cage and o.type == 'MESH']
    if len(others) == 1:
        return others[0]
    raise ValueError("choose the scan: select it together with the cage, or give its name")


def preferences(context=None):
    """(threads, memory budget in bytes) from the add-on's preferences (0, 0 when the add-on is
    not registered as such, e.g. imported by a script)."""
    context = context or bpy.context
    addon = context.preferences.addons.get(__package__) if context.preferences else None
    prefs = getattr(addon, "preferences", None)
    if prefs is None:
        return 0, 0
    return int(prefs.threads), int(prefs.memory_budget_mb) * (1 << 20)


def _undo_push(message):
    """An undo step for what the finish step changed (seconds taken; None when Blender has no undo
    stack here, e.g. in background mode)."""
    t = time.perf_counter()
    try:
        if not bpy.ops.ed.undo_push.poll():
            return None
        bpy.ops.ed.undo_push(message=message)
    except Exception:  # no window / no undo stack: nothing to push onto
        return None
    return time.perf_counter() - t


# --- jobs ------------------------------------------------------------------------------------------
class Job:
    """One SDK job. `work` (a callable of the job) runs the SDK calls and returns the result that
    `finish` (a callable (context, result) -> report text) hands over to Blender."""

    def __init__(self, name, work, finish, context):
        if "_OT_" in name:   # a registered class's bl_idname reads CAGEKIT_OT_fit
            prefix, _, rest = name.partition("_OT_")
            name = prefix.lower() + "." + rest
        self.name = name
        self.work = work
        self.finish = finish
        threads, budget = preferences(context)
        self.threads = threads
        self.stage, self.fraction = "", 0.0
        self.cancel_requested = False
        self.cancel_time = None
        self.end_time = None
        self.result = None
        self.error = None
        self.sync_progress = None        # a _Progress on the main thread (execute())
        self.timings = {}
        self.marks = {}                  # perf_counter() at the steps' ends (the benchmark reads them)
        self.modal_times = []            # perf_counter() at each call of the modal handler
        self.cancel_call = None          # len(modal_times) when the modal handler cancelled
        self.progress_calls = 0
        self._held = False
        self.ctx = sdk().Context(progress=self._progress, memory_budget_bytes=budget)

    # the SDK's progress callback: the worker thread (modal) or the main thread (execute)
    def _progress(self, stage, fraction):
        self.stage, self.fraction = stage, float(fraction)
        self.progress_calls += 1
        if self.sync_progress is not None:
            self.sync_progress(stage, fraction)
        if TEST_HOLD_FRACTION is not None and not self._held and self.fraction >= TEST_HOLD_FRACTION:
            self._held = True
            limit = time.perf_counter() + 60.0
            while not self.cancel_requested and time.perf_counter() < limit:
                time.sleep(0.005)
        return not self.cancel_requested

    def cancel(self):
        """Any thread: the SDK stops at its next check (the context's cancel flag, and the progress
        callback returns False)."""
        if not self.cancel_requested:
            self.cancel_time = time.perf_counter()
        self.cancel_requested = True
        try:
            self.ctx.cancel()
        except Exception:
            pass

    def run(self):
        t = time.perf_counter()
        try:
            self.result = self.work(self)
        except BaseException as e:  # stored; the main thread reports it
            self.error = e
        finally:
            self.end_time = time.perf_counter()
            self.timings["work"] = self.end_time - t

    def cancelled(self):
        return self.cancel_requested or isinstance(self.error, getattr(sdk(), "CancelledError", ()))

    def record(self, state, message=""):
        global last_job
        latency = None
        if self.cancel_time is not None and self.end_time is not None:
            latency = max(self.end_time - self.cancel_time, 0.0)
        last_job = {"operator": self.name, "state": state, "message": message, "timings": dict(self.timings),
                    "marks": dict(self.marks), "cancel_latency": latency,
                    "modal_max_gap": max((b - a for a, b in zip(self.modal_times, self.modal_times[1:])),
                                         default=None), "modal_calls": len(self.modal_times),
                    "progress_calls": self.progress_calls,
                    # handler calls after the one that cancelled (0: the operator ended in that call)
                    "modal_calls_after_cancel": (len(self.modal_times) - self.cancel_call
                                                 if self.cancel_call is not None else None)}


class _JobOperator:
    """Mixin: invoke() goes modal with the work on a thread, execute() runs it synchronously.
    Subclasses define `_start(context) -> Job` (the start step, main thread) and `undo_message`."""

    _settings_props = ()    # options copied from the scene's CageKit settings when not set

    def _apply_scene_settings(self, context):
        settings = getattr(context.scene, "cagekit", None)
        if settings is None:
            return
        for name in self._settings_props:
            if not self.properties.is_property_set(name) and hasattr(settings, name):
                setattr(self, name, getattr(settings, name))

    def _begin(self, context):
        t = time.perf_counter()
        job = self._start(context)
        job.marks["start_begin"], job.marks["start_end"] = t, time.perf_counter()
        job.timings["start"] = job.marks["start_end"] - t
        return job

    def _end(self, context, job):
        """The finish step (main thread): report, hand-over, undo push. Returns the operator's set."""
        job.marks["end"] = time.perf_counter()
        if job.cancel_time is not None:
            job.marks["cancel"] = job.cancel_time
        if job.end_time is not None:
            job.marks["work_end"] = job.end_time
        if job.error is not None or job.cancel_requested:
            if job.cancelled():
                job.record("CANCELLED", "cancelled")
                self.report({'INFO'}, "CageKit: %s cancelled; nothing was changed" % self.bl_label)
                return {'CANCELLED'}
            job.record("FAILED", _message(job.error))
            return _fail(self, job.error)
        t = time.perf_counter()
        try:
            text = job.finish(context, job.result)
        except Exception as e:
            job.record("FAILED", _message(e))
            return _fail(self, e)
        finally:
            job.result = None
        job.timings["handover"] = time.perf_counter() - t
        job.marks["handover_begin"] = t
        undo = _undo_push("CageKit: %s" % self.bl_label)
        if undo is not None:
            job.timings["undo_push"] = undo
        job.marks["finish_end"] = time.perf_counter()
        job.record("FINISHED", text or "")
        if text:
            self.report({'INFO'}, text)
        return {'FINISHED'}

    # scripts and background mode
    def execute(self, context):
        progress = _Progress(context)
        try:
            try:
                job = self._begin(context)
            except Exception as e:  # cagekit errors, ImportError of the library, bad input
                return _fail(self, e)
            job.sync_progress = progress
            job.run()
            return self._end(context, job)
        finally:
            progress.end()

    # the UI: a worker thread and a modal handler
    def invoke(self, context, event):
        self._apply_scene_settings(context)
        if context.window is None:
            return self.execute(context)
        try:
            job = self._begin(context)
        except Exception as e:
            return _fail(self, e)
        self._job = job
        self._thread = threading.Thread(target=job.run, name="cagekit " + self.bl_idname, daemon=True)
        wm = context.window_manager
        self._timer = wm.event_timer_add(0.1, window=context.window)
        wm.modal_handler_add(self)
        wm.progress_begin(0, 1000)
        running_jobs.append(job)
        self._status_text, self._status_time, self._status_percent = None, 0.0, -1
        self._status(context, force=True)
        self._thread.start()
        return {'RUNNING_MODAL'}

    def _status(self, context, force=False):
        """The status-bar text and the progress indicator. A status-bar change redraws regions of the
        window, which costs tenths of a second with software OpenGL: the text changes at most every
        STATUS_INTERVAL seconds (and on a cancel), the indicator when the whole percent changes."""
        job = self._job
        percent = int(100 * min(max(job.fraction, 0.0), 1.0))
        if job.cancel_requested:
            text = "CageKit %s: cancelling..." % self.bl_label
        else:
            text = "CageKit %s: %s %d%%  (Esc / right-click: cancel)" % (self.bl_label, job.stage or "starting",
                                                                        percent)
        now = time.perf_counter()
        if text != self._status_text and (force or now - self._status_time >= STATUS_INTERVAL):
            self._status_text, self._status_time = text, now
            try:
                context.workspace.status_text_set(text)
            except Exception:
                pass
        if percent != self._status_percent:
            self._status_percent = percent
            try:
                context.window_manager.progress_update(10 * percent)
            except Exception:
                pass

    def _cleanup(self, context):
        wm = context.window_manager
        if getattr(self, "_timer", None) is not None:
            wm.event_timer_remove(self._timer)
            self._timer = None
        try:
            wm.progress_end()
        except Exception:
            pass
        try:
            context.workspace.status_text_set(None)
        except Exception:
            pass
        if self._job in running_jobs:
            running_jobs.remove(self._job)

    def modal(self, context, event):
        job = self._job
        job.modal_times.append(time.perf_counter())
        if event.type in {'ESC', 'RIGHTMOUSE'} and event.value == 'PRESS':
            job.cancel()
            if job.cancel_call is None:
                job.cancel_call = len(job.modal_times)
            self._thread.join(timeout=CANCEL_WAIT)
            if self._thread.is_alive():
                self._status(context, force=True)
                return {'RUNNING_MODAL'}
            self._cleanup(context)
            return self._end(context, job)
        if self._thread.is_alive():
            if event.type == 'TIMER':
                self._status(context)
            return {'PASS_THROUGH'}
        self._thread.join()
        self._cleanup(context)
        return self._end(context, job)

    def cancel(self, context):
        """Blender ends the modal operator (a file is loaded, the window closes): cancel the work
        and drop its result."""
        job = getattr(self, "_job", None)
        if job is not None:
            job.cancel()
            self._thread.join(timeout=5.0)
            job.record("CANCELLED", "ended by Blender")
            self._cleanup(context)


# --- sharp edges the user marked --------------------------------------------------------------------
def marked_sharp_edges(obj, sharp=True, seams=False, face_sets=False):
    """(E, 2) uint32 vertex pairs of the object's edges marked sharp, seams, and borders between
    face sets (the int face attribute '.sculpt_face_set' or 'sculpt_face_set'; Blender 3.x face
    maps when neither exists)."""
    me = obj.data
    n = len(me.edges)
    mask = np.zeros(n, dtype=bool)
    flags = np.zeros(n, dtype=bool)
    if sharp:
        me.edges.foreach_get("use_edge_sharp", flags)
        mask |= flags
    if seams:
        me.edges.foreach_get("use_seam", flags)
        mask |= flags
    if face_sets and len(me.polygons):
        ids = _face_set_ids(obj)
        if ids is not None:
            loops_edge = np.empty(len(me.loops), dtype=np.int32)
            me.loops.foreach_get("edge_index", loops_edge)
            total = np.empty(len(me.polygons), dtype=np.int32)
            me.polygons.foreach_get("loop_total", total)
            start = np.empty(len(me.polygons), dtype=np.int32)
            me.polygons.foreach_get("loop_start", start)
            face_of_loop = np.empty(len(me.loops), dtype=np.int64)
            local = np.arange(int(total.sum())) - np.repeat(np.cumsum(total) - total, total)
            face_of_loop[np.repeat(start, total) + local] = np.repeat(np.arange(len(total)), total)
            lo = np.full(n, np.iinfo(np.int64).max, dtype=np.int64)
            hi = np.full(n, np.iinfo(np.int64).min, dtype=np.int64)
            set_of_loop = ids[face_of_loop]
            np.minimum.at(lo, loops_edge, set_of_loop)
            np.maximum.at(hi, loops_edge, set_of_loop)
            counts = np.bincount(loops_edge, minlength=n)
            mask |= (counts >= 2) & (lo != hi)
    return meshio.edge_pairs(me)[mask].astype(np.uint32)


def _face_set_ids(obj):
    me = obj.data
    for name in (".sculpt_face_set", "sculpt_face_set"):
        attr = me.attributes.get(name)
        if attr is not None and attr.domain == 'FACE' and attr.data_type == 'INT':
            ids = np.empty(len(me.polygons), dtype=np.int32)
            attr.data.foreach_get("value", ids)
            return ids.astype(np.int64)
    if len(getattr(obj, "face_maps", ())) and "face_maps" in me.bl_rna.properties and len(me.face_maps):
        ids = np.empty(len(me.polygons), dtype=np.int32)
        me.face_maps[0].data.foreach_get("value", ids)
        return ids.astype(np.int64)
    return None


# --- scan_to_cage ----------------------------------------------------------------------------------
METHODS = [('SIMPLIFY', "Simplify", "Structure-preserving simplification (thesis ch. 3): a cage of about Faces faces"),
           ('QUAD', "Quad", "Two-step quad-dominant remeshing (thesis ch. 6): VSA regions meshed with quads"),
           ('ANISOTROPIC', "Anisotropic", "Curvature-line remeshing (thesis ch. 5): quads along the principal "
                                          "curvature directions")]

SCAN_TO_CAGE_PROPS = {
    "method": EnumProperty(name="Method", items=METHODS, default='SIMPLIFY'),
    # simplify
    "faces": IntProperty(name="Faces", default=200, min=2, max=1000000,
                         description="Simplify: faces of the simplified mesh (the finest level with at most this "
                                     "many); splitting its polygons into quads gives the cage more faces. Also "
                                     "the target of the fallback to Simplify"),
    "crease_rule": EnumProperty(
        name="Creases", default='SHARP_INPUT',
        items=[('SHARP_INPUT', "Where the Mesh Is Sharp",
                "Crease cage edges only along the mesh's own sharp edges (smooth organic scans, crisp CAD edges)"),
               ('CLUSTER_ANGLE', "By Cluster Angle",
                "Crease cage edges between simplified regions whose normals differ by more than the crease "
                "angle (the thesis's rule; organic scans look faceted)")]),
    "feature_angle": FloatProperty(name="Feature Angle", default=math.radians(40.0), min=0.0, max=math.pi,
                                   subtype='ANGLE', description="Where the Mesh Is Sharp: mesh edges whose faces "
                                                                "meet at more than this angle may be sharp features"),
    "crease_angle": FloatProperty(name="Crease Angle", default=math.radians(30.0), min=0.0, max=math.pi,
                                  subtype='ANGLE', description="By Cluster Angle: cage edges between regions whose "
                                                               "normals differ by more are infinitely sharp creases"),
    # quad
    "quad_edge_length": FloatProperty(name="Edge Length", default=0.05, min=1e-4, max=1.0, precision=4,
                                      description="Quad: length of the cage's edges, as a fraction of the "
                                                  "bounding-box diagonal"),
    "quad_regions": IntProperty(name="Regions", default=30, min=0, max=100000,
                                description="Quad: VSA regions (0: by the region tolerance)"),
    "quad_crease_angle": FloatProperty(name="Crease Angle", default=math.radians(40.0), min=0.0, max=math.pi,
                                       subtype='ANGLE', description="Quad: region borders sharper than this are "
                                                                    "creases"),
    "quad_refinement_passes": IntProperty(name="Refinement Passes", default=1, min=0, max=20),
    # anisotropic
    "aniso_tolerance": FloatProperty(name="Tolerance", default=0.002, min=1e-6, max=0.5, precision=4,
                                     description="Anisotropic: distance tolerance as a fraction of the diagonal "
                                                 "(smaller: more faces)"),
    "aniso_feature_angle": FloatProperty(name="Feature Angle", default=math.radians(40.0), min=0.0, max=math.pi,
                                         subtype='ANGLE', description="Anisotropic: feature lines (creases) where "
                                                                      "faces meet at more than this angle"),
    "aniso_max_face_valence": IntProperty(name="Max Face Valence", default=5, min=4, max=64),
    "aniso_curvature_radius": FloatProperty(name="Curvature Radius", default=0.01, min=1e-5, max=1.0, precision=4,
                                            description="Anisotropic: radius of the curvature estimate, as a "
                                                        "fraction of the diagonal"),
    "fallback_to_simplify": BoolProperty(name="Fall Back to Simplify", default=True,
                                         description="When Quad or Anisotropic gives no good cage, use Simplify"),
    # guides
    "use_sharp_edges": BoolProperty(name="Sharp Edges", default=True,
                                    description="Edges marked sharp are input sharp edges (creases of the cage)"),
    "use_seams": BoolProperty(name="Seams", default=False, description="Seams are input sharp edges"),
    "use_face_sets": BoolProperty(name="Face Set Borders", default=False,
                                  description="Borders between face sets are input sharp edges"),
    # fit and the result
    "passes": IntProperty(name="Fitting Passes", default=5, min=0, max=100,
                          description="Passes of fitting the cage's limit surface to the mesh (0: no fitting)"),
    "keep_crease_vertices": BoolProperty(name="Keep Crease Vertices", default=False,
                                         description="Do not move vertices on crease edges while fitting"),
    "levels": IntProperty(name="Subdivision Levels", default=2, min=0, max=6,
                          description="Levels of the Subdivision Surface modifier (viewport and render)"),
}


def draw_scan_to_cage_options(layout, props):
    layout.prop(props, "method")
    col = layout.column(align=True)
    if props.method == 'SIMPLIFY':
        col.prop(props, "faces")
        col.prop(props, "crease_rule", text="")
        col.prop(props, "feature_angle" if props.crease_rule == 'SHARP_INPUT' else "crease_angle")
    elif props.method == 'QUAD':
        col.prop(props, "quad_edge_length")
        col.prop(props, "quad_regions")
        col.prop(props, "quad_crease_angle")
        col.prop(props, "quad_refinement_passes")
    else:
        col.prop(props, "aniso_tolerance")
        col.prop(props, "aniso_feature_angle")
        col.prop(props, "aniso_max_face_valence")
        col.prop(props, "aniso_curvature_radius")
    if props.method != 'SIMPLIFY':
        col.prop(props, "fallback_to_simplify")
        col.prop(props, "faces", text="Fallback Faces")
    row = layout.row(align=True)
    row.label(text="Guides:")
    row.prop(props, "use_sharp_edges", toggle=True)
    row.prop(props, "use_seams", toggle=True)
    row.prop(props, "use_face_sets", toggle=True, text="Face Sets")
    col = layout.column(align=True)
    col.prop(props, "passes")
    col.prop(props, "keep_crease_vertices")
    col.prop(props, "levels")


class CAGEKIT_OT_scan_to_cage(_JobOperator, bpy.types.Operator):
    """Make a Catmull-Clark cage of the active mesh (simplify, quad or anisotropic remeshing, with
    the edges marked sharp as creases), fitted to the mesh, with a Subdivision Surface modifier.
    Runs in the background: Esc or right-click cancels"""

    bl_idname = "cagekit.scan_to_cage"
    bl_label = "Scan to Cage"
    bl_options = set()   # no redo panel: it would rerun the whole job (undo: explicit push)
    __annotations__ = dict(SCAN_TO_CAGE_PROPS)
    _settings_props = tuple(SCAN_TO_CAGE_PROPS)

    @classmethod
    def poll(cls, context):
        return _active_mesh(context)

    def draw(self, context):
        draw_scan_to_cage_options(self.layout, self)

    def _start(self, context):
        scan = context.active_object
        _check_mesh(scan, "active object")
        scan_name = scan.name
        pos = meshio.positions(scan)
        sizes, flat = meshio.faces(scan)
        sharp = marked_sharp_edges(scan, self.use_sharp_edges, self.use_seams, self.use_face_sets)
        method = self.method.lower()
        opts = dict(method=method, faces=self.faces,
                    crease_angle_degrees=math.degrees(self.crease_angle),
                    crease_rule="sharp-input" if self.crease_rule == 'SHARP_INPUT' else "cluster-angle",
                    feature_angle_degrees=math.degrees(self.feature_angle),
                    fallback_to_simplify=self.fallback_to_simplify,
                    sharp_edges=sharp if len(sharp) else None)
        passes = self.passes
        keep = self.keep_crease_vertices
        levels = self.levels
        quad = dict(edge_length=self.quad_edge_length, regions=self.quad_regions,
                    crease_angle_degrees=math.degrees(self.quad_crease_angle),
                    refinement_passes=self.quad_refinement_passes)
        aniso = dict(tolerance=self.aniso_tolerance, feature_angle_degrees=math.degrees(self.aniso_feature_angle),
                     max_face_valence=self.aniso_max_face_valence, curvature_radius=self.aniso_curvature_radius)

        def work(job):
            ck = sdk()
            opts["quad"] = dict(quad, threads=job.threads)
            opts["anisotropic"] = dict(aniso, threads=job.threads)
            opts["fit"] = {"max_passes": passes, "keep_crease_vertices": keep, "threads": job.threads}
            with ck.Mesh.from_arrays(pos, (sizes, flat), context=job.ctx) as mesh:
                cage, limit, report = ck.scan_to_cage(mesh, **opts)
            limit.close()
            with cage:
                cage_pos = cage.positions
                cage_sizes, cage_flat = cage.face_arrays()
                creases = cage.creases
                corners = cage.corners
                holes = len(cage.holes)
                rule = cage.boundary_rule
            return dict(pos=cage_pos, sizes=cage_sizes, flat=cage_flat, creases=creases, corners=corners,
                        holes=holes, rule=rule, report=report, sharp_given=len(sharp))

        def finish(context, r):
            return self._hand_over(context, scan_name, levels, passes, r)

        return Job(self.bl_idname, work, finish, context)

    def _hand_over(self, context, scan_name, levels, passes, r):
        ck = sdk()
        report = r["report"]
        scan = bpy.data.objects.get(scan_name)
        me = meshio.new_mesh(scan_name + "_cage", r["pos"], r["sizes"], r["flat"])
        creased, corners, two_crease = meshio.write_cage_tags_into_mesh(me, r["creases"], r["corners"])
        obj = bpy.data.objects.new(scan_name + "_cage", me)
        collections = (scan.users_collection if scan is not None else ()) or (context.scene.collection,)
        collections[0].objects.link(obj)
        if scan is not None:
            obj.matrix_world = scan.matrix_world.copy()
        obj["cagekit_scan"] = scan_name
        obj["cagekit_method"] = report.used_method.name.lower()
        obj["cagekit_level_faces"] = int(report.level_faces)
        obj["cagekit_target_faces"] = int(report.simplify_target_used)
        obj["cagekit_fit_fairing"] = float(report.fit_fairing_used)
        obj["cagekit_sharp_edges"] = int(report.sharp_edges)
        if passes > 0:
            obj["cagekit_fit_rms_rel"] = float(report.fit_final.rms_rel)
        mod = obj.modifiers.new("CageKit Subdivision", 'SUBSURF')
        mod.subdivision_type = 'CATMULL_CLARK'
        mod.levels = levels
        mod.render_levels = levels
        mod.use_creases = True
        # Refined vertices, not their limit positions: level by level the same points as
        # OpenSubdiv's uniform refinement (cagekit subdivide); boundary rule "edges only".
        mod.use_limit_surface = False
        mod.boundary_smooth = 'ALL' if r["rule"] == ck.BoundaryRule.EDGES_ONLY else 'PRESERVE_CORNERS'
        obj.show_wire = True
        for o in context.selected_objects:
            o.select_set(False)
        obj.select_set(True)
        context.view_layer.objects.active = obj
        conditioned = report.input_faces != report.conditioned_faces or report.welded_vertices or report.flipped_faces
        if conditioned:
            self.report({'INFO'}, "CageKit: the scan was conditioned: %d -> %d faces, %d vertices welded, "
                                  "%d faces flipped" % (report.input_faces, report.conditioned_faces,
                                                        report.welded_vertices, report.flipped_faces))
        if report.fallback:
            self.report({'WARNING'}, "CageKit: %s fell back to simplify: %s"
                        % (report.requested_method.name.lower(), report.fallback_reason))
        if r["sharp_given"]:
            self.report({'INFO'}, "CageKit: %d marked edges given as sharp, %d found on the conditioned scan, "
                                  "%d dropped" % (r["sharp_given"], report.sharp_edges, report.sharp_edges_dropped))
        if r["holes"]:
            self.report({'WARNING'}, "CageKit: %d hole faces are not represented in Blender" % r["holes"])
        if two_crease:
            self.report({'WARNING'}, "CageKit: %d vertices have only two edges, both creased: Blender's "
                                     "subdivision makes them corners, CageKit's does not" % two_crease)
        text = "CageKit: %s cage of %d faces (%d quads), %d crease edges" % (
            report.used_method.name.lower(), len(me.polygons), report.cage_quads, creased)
        if passes > 0:
            text += ", fitted (rms %.2g of the diagonal)" % report.fit_final.rms_rel
        return text


# --- fit -------------------------------------------------------------------------------------------
class CAGEKIT_OT_fit(_JobOperator, bpy.types.Operator):
    """Fit the active cage's limit surface to a scan (moves the cage's vertices). Runs in the
    background: Esc or right-click cancels"""

    bl_idname = "cagekit.fit"
    bl_label = "Fit Cage"
    bl_options = set()   # no redo panel (undo: explicit push)

    scan: StringProperty(name="Scan", default="",
                         description="Scan object (empty: the cage's scan, or the other selected mesh)")
    passes: IntProperty(name="Fitting Passes", default=5, min=1, max=100)
    keep_crease_vertices: BoolProperty(name="Keep Crease Vertices", default=False)

    @classmethod
    def poll(cls, context):
        return _active_mesh(context)

    def _apply_scene_settings(self, context):
        settings = getattr(context.scene, "cagekit", None)
        if settings is None:
            return
        if not self.properties.is_property_set("passes"):
            self.passes = max(1, settings.passes)
        if not self.properties.is_property_set("keep_crease_vertices"):
            self.keep_crease_vertices = settings.keep_crease_vertices

    def _start(self, context):
        cage_obj = context.active_object
        if cage_obj.mode == 'EDIT':
            raise ValueError("leave edit mode on the cage first")
        scan = _cage_and_scan(context, cage_obj, self.scan)
        cage_name = cage_obj.name
        scan_pos = meshio.transform(_relative(cage_obj, scan), meshio.positions(scan))
        scan_faces = meshio.faces(scan)
        cage_arrays = meshio.cage_arrays(cage_obj)
        passes, keep = self.passes, self.keep_crease_vertices

        def work(job):
            ck = sdk()
            with ck.Mesh.from_arrays(scan_pos, scan_faces, context=job.ctx) as mesh, \
                    ck.Cage.from_arrays(context=job.ctx, **cage_arrays) as cage:
                fitted, report = ck.fit(cage, mesh, max_passes=passes, keep_crease_vertices=keep,
                                        threads=job.threads)
                with fitted:
                    return fitted.positions, report

        def finish(context, result):
            pos, report = result
            obj = bpy.data.objects.get(cage_name)
            if obj is None or obj.type != 'MESH' or len(obj.data.vertices) != len(pos):
                raise ValueError("the cage %r was removed or changed its vertices during the fit" % cage_name)
            if obj.mode == 'EDIT':
                raise ValueError("the cage %r entered edit mode during the fit; fit again" % cage_name)
            meshio.write_positions(obj, pos)
            rms = report.passes[-1].rms_rel if report.passes else float("nan")
            obj["cagekit_fit_rms_rel"] = float(rms)
            return "CageKit: fitted in %d passes (rms %.2g of the diagonal)" % (len(report.passes) - 1, rms)

        return Job(self.bl_idname, work, finish, context)


# --- bind / unbind ---------------------------------------------------------------------------------
class CAGEKIT_OT_bind(_JobOperator, bpy.types.Operator):
    """Bind a scan to the active cage: the scan then follows edits of the cage live. Runs in the
    background: Esc or right-click cancels"""

    bl_idname = "cagekit.bind"
    bl_label = "Bind Scan to Cage"
    bl_options = set()   # (undo: explicit push; undoing it ends the binding, handlers.on_undo)

    scan: StringProperty(name="Scan", default="",
                         description="Scan object (empty: the cage's scan, or the other selected mesh)")
    local_frame: BoolProperty(name="Local Frame", default=False,
                              description="Keep the whole offset in the surface's frame (else along the normal)")

    @classmethod
    def poll(cls, context):
        return _active_mesh(context)

    def _start(self, context):
        cage_obj = context.active_object
        scan = _cage_and_scan(context, cage_obj, self.scan)
        scan_name, cage_name = scan.name, cage_obj.name
        matrix = _relative(scan, cage_obj)
        rest_scan = meshio.positions(scan)
        scan_faces = meshio.faces(scan)
        cage_arrays = meshio.cage_arrays(cage_obj, matrix)
        mode = "local_frame" if self.local_frame else "normal"

        def work(job):
            ck = sdk()
            with ck.Mesh.from_arrays(rest_scan, scan_faces, context=job.ctx) as mesh, \
                    ck.Cage.from_arrays(context=job.ctx, **cage_arrays) as cage:
                binding = ck.bind(cage, mesh, mode=mode, threads=job.threads)
            try:
                deformer = ck.CpuDeformer(binding, threads=job.threads)
                control = binding.control_points()
                rest_deformed, _ = deformer.deform(control, normals=False)
            except BaseException:
                binding.close()
                raise
            return binding, deformer, control, rest_deformed

        def finish(context, result):
            binding, deformer, control, rest_deformed = result
            entry = handlers.Bound(scan_name, cage_name, binding, deformer, matrix, control, rest_deformed, rest_scan)
            scan_obj = bpy.data.objects.get(scan_name)
            if scan_obj is None or bpy.data.objects.get(cage_name) is None or \
                    len(scan_obj.data.vertices) != len(rest_scan):
                entry.close()
                raise ValueError("the scan or the cage was removed or changed during the bind")
            handlers.add(entry)
            scan_obj["cagekit_cage"] = cage_name
            return "CageKit: %r follows edits of %r (%d vertices, %d control points)" % (
                scan_name, cage_name, len(rest_scan), len(control))

        return Job(self.bl_idname, work, finish, context)


class CAGEKIT_OT_unbind(bpy.types.Operator):
    """End the live bindings of the active object (as scan or as cage)"""

    bl_idname = "cagekit.unbind"
    bl_label = "Unbind"
    bl_options = {'REGISTER', 'UNDO'}

    @classmethod
    def poll(cls, context):
        return context.active_object is not None

    def execute(self, context):
        name = context.active_object.name
        scans = [s for s, e in handlers.bindings().items() if s == name or e.cage_name == name]
        count = handlers.remove_for_object(name)
        if count == 0:
            self.report({'WARNING'}, "CageKit: %r has no live binding" % name)
            return {'CANCELLED'}
        for s in scans:
            obj = bpy.data.objects.get(s)
            if obj is not None and "cagekit_cage" in obj:
                del obj["cagekit_cage"]
        self.report({'INFO'}, "CageKit: %d binding(s) ended" % count)
        return {'FINISHED'}


class CAGEKIT_OT_cancel_jobs(bpy.types.Operator):
    """Cancel the running CageKit jobs"""

    bl_idname = "cagekit.cancel_jobs"
    bl_label = "Cancel CageKit Jobs"
    bl_options = {'INTERNAL'}

    @classmethod
    def poll(cls, context):
        return bool(running_jobs)

    def execute(self, context):
        for job in list(running_jobs):
            job.cancel()
        return {'FINISHED'}


class CageKitSettings(bpy.types.PropertyGroup):
    """The sidebar's options of Scan to Cage (and Fit's passes), copied into the operators."""
    __annotations__ = dict(SCAN_TO_CAGE_PROPS)


class CageKitPreferences(bpy.types.AddonPreferences):
    bl_idname = __package__

    threads: IntProperty(name="Threads", default=0, min=0, max=1024,
                         description="Worker threads of the SDK's remeshing, fitting and binding (0: all cores)")
    memory_budget_mb: IntProperty(name="Memory Budget (MiB)", default=0, min=0, max=1 << 24,
                                  description="Per-call memory budget of the SDK (0: unlimited); a job that would "
                                              "need more fails with an out-of-memory report before allocating")

    def draw(self, context):
        row = self.layout.row()
        row.prop(self, "threads")
        row.prop(self, "memory_budget_mb")


classes = (CageKitSettings, CageKitPreferences, CAGEKIT_OT_scan_to_cage, CAGEKIT_OT_fit, CAGEKIT_OT_bind,
           CAGEKIT_OT_unbind, CAGEKIT_OT_cancel_jobs)
