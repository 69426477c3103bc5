# SPDX-License-Identifier: GPL-3.0-or-later
"""The add-on's operators: cagekit.scan_to_cage, cagekit.fit, cagekit.bind, cagekit.unbind.

Every SDK failure (a cagekit exception, or the library failing to load) becomes an operator
error report and {'CANCELLED'}; nothing is left half made (objects are created only after every
SDK call succeeded).
"""
import math

import bpy
import numpy as np
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, StringProperty

from . import handlers, meshio
from ._sdk import sdk



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
    driven by CageKit's progress callback: stage `name` covers [lo, hi] of the bar."""

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
        return None   # never cancels

    def end(self):
        if self.wm is not None:
            try:
                self.wm.progress_end()
            except Exception:
                pass


def _fail(op, e):
    message = getattr(e, "message", None) or str(e) or type(e).__name__
    op.report({'ERROR'}, "CageKit: %s" % message)
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


class CAGEKIT_OT_scan_to_cage(bpy.types.Operator):
    """Make a Catmull-Clark cage of the active mesh: structure-preserving simplification to a
    quad-dominant cage with crease edges, fitted to the mesh, with a Subdivision Surface modifier"""

    bl_idname = "cagekit.scan_to_cage"
    bl_label = "Scan to Cage"
    bl_options = {'REGISTER', 'UNDO'}

    faces: IntProperty(name="Faces", default=200, min=2, max=1000000,
                       description="Faces of the simplified mesh (the finest level with at most this many); "
                                   "splitting its polygons into quads gives the cage more faces")
    passes: IntProperty(name="Fitting Passes", default=5, min=0, max=100,
                        description="Passes of fitting the cage's limit surface to the mesh (0: no fitting)")
    crease_rule: EnumProperty(
        name="Creases", default='SHARP_INPUT',
        items=[('SHARP_INPUT', "Where the Mesh Is Sharp",
                "Crease cage edges only along the mesh's own sharp edges (smooth organic scans, crisp CAD edges)"),
               ('CLUSTER_ANGLE', "By Cluster Angle",
                "Crease cage edges between simplified regions whose normals differ by more than the crease "
                "angle (the thesis's rule; organic scans look faceted)")])
    feature_angle: FloatProperty(name="Feature Angle", default=math.radians(40.0), min=0.0, max=math.pi,
                                 subtype='ANGLE', description="Where the Mesh Is Sharp: mesh edges whose faces meet "
                                                              "at more than this angle may be sharp features")
    crease_angle: FloatProperty(name="Crease Angle", default=math.radians(30.0), min=0.0, max=math.pi,
                                subtype='ANGLE', description="By Cluster Angle: cage edges between regions whose "
                                                             "normals differ by more are infinitely sharp creases")
    keep_crease_vertices: BoolProperty(name="Keep Crease Vertices", default=False,
                                       description="Do not move vertices on crease edges while fitting")
    levels: IntProperty(name="Subdivision Levels", default=2, min=0, max=6,
                        description="Levels of the Subdivision Surface modifier (viewport and render)")

    @classmethod
    def poll(cls, context):
        return _active_mesh(context)

    def execute(self, context):
        scan = context.active_object
        progress = _Progress(context)
        try:
            return self._run(context, scan, progress)
        except Exception as e:  # cagekit errors, ImportError of the library, bad input
            return _fail(self, e)
        finally:
            progress.end()

    def _run(self, context, scan, progress):
        _check_mesh(scan, "active object")
        ck = sdk()
        ctx = ck.Context(progress=progress)
        with meshio.scan_mesh(scan, context=ctx) as mesh:
            # The SDK's whole journey (conditioning -> simplification -> cage -> fit -> a judged
            # result: QualityError instead of a bad surface).
            progress.stage(0.0, 1.0)
            cage, limit, report = ck.scan_to_cage(
                mesh, faces=self.faces, crease_angle_degrees=math.degrees(self.crease_angle),
                crease_rule="sharp-input" if self.crease_rule == 'SHARP_INPUT' else "cluster-angle",
                feature_angle_degrees=math.degrees(self.feature_angle),
                fit={"max_passes": self.passes, "keep_crease_vertices": self.keep_crease_vertices})
            limit.close()
            level_faces = report.level_faces
            target_faces = report.simplify_target_used  # raised by the journey's remedies
            fit_fairing = report.fit_fairing_used
            rms = report.fit_final.rms_rel if self.passes > 0 else None
            try:
                pos = cage.positions
                sizes, flat = cage.face_arrays()
                me = meshio.new_mesh(scan.name + "_cage", pos, sizes, flat)
                creased, corners, two_crease = meshio.write_cage_into_mesh(me, cage)
                holes = len(cage.holes)
                rule = cage.boundary_rule
            finally:
                cage.close()
        obj = bpy.data.objects.new(scan.name + "_cage", me)
        collections = scan.users_collection or (context.scene.collection,)
        collections[0].objects.link(obj)
        obj.matrix_world = scan.matrix_world.copy()
        obj["cagekit_scan"] = scan.name
        obj["cagekit_level_faces"] = int(level_faces)
        obj["cagekit_target_faces"] = int(target_faces)
        obj["cagekit_fit_fairing"] = float(fit_fairing)
        if rms is not None:
            obj["cagekit_fit_rms_rel"] = float(rms)
        mod = obj.modifiers.new("CageKit Subdivision", 'SUBSURF')
        mod.subdivision_type = 'CATMULL_CLARK'
        mod.levels = self.levels
        mod.render_levels = self.levels
        mod.use_creases = True
        # Refined vertices, not their limit positions: level by level the same points as
        # OpenSubdiv's uniform refinement (cagekit subdivide); boundary rule "edges only".
        mod.use_limit_surface = False
        mod.boundary_smooth = 'ALL' if rule == ck.BoundaryRule.EDGES_ONLY else 'PRESERVE_CORNERS'
        obj.show_wire = True
        for o in context.selected_objects:
            o.select_set(False)
        obj.select_set(True)
        context.view_layer.objects.active = obj
        text = "CageKit: cage of %d faces (%d quads), %d crease edges" % (len(me.polygons), report.cage_quads, creased)
        conditioned = report.input_faces != report.conditioned_faces or report.welded_vertices or report.flipped_faces
        if conditioned:
            self.report({'INFO'}, "CageKit: the scan was conditioned: %d -> %d faces, %d vertices welded, "
                                  "%d faces flipped" % (report.input_faces, report.conditioned_faces,
                                                        report.welded_vertices, report.flipped_faces))
        if rms is not None:
            text += ", fitted (rms %.2g of the diagonal)" % rms
        self.report({'INFO'}, text)
        if holes:
            self.report({'WARNING'}, "CageKit: %d hole faces are not represented in Blender" % holes)
        if two_crease:
            self.report({'WARNING'}, "CageKit: %d vertices have only two edges, both creased: Blender's "
                                     "subdivision makes them corners, CageKit's does not" % two_crease)
        return {'FINISHED'}


class CAGEKIT_OT_fit(bpy.types.Operator):
    """Fit the active cage's limit surface to a scan (moves the cage's vertices)"""

    bl_idname = "cagekit.fit"
    bl_label = "Fit Cage"
    bl_options = {'REGISTER', 'UNDO'}

    scan: StringProperty(name="Scan", default="",
                         description="Scan object (empty: the cage's scan, or the other selected mesh)")
    passes: IntProperty(name="Fitting Passes", default=5, min=1, max=100)
    keep_crease_vertices: BoolProperty(name="Keep Crease Vertices", default=False)

    @classmethod
    def poll(cls, context):
        return _active_mesh(context)

    def execute(self, context):
        cage_obj = context.active_object
        progress = _Progress(context)
        try:
            scan = _cage_and_scan(context, cage_obj, self.scan)
            ck = sdk()
            ctx = ck.Context(progress=progress)
            with meshio.scan_mesh(scan, _relative(cage_obj, scan), context=ctx) as mesh, \
                    meshio.cage_from_object(cage_obj, context=ctx) as cage:
                fitted, report = ck.fit(cage, mesh, max_passes=self.passes,
                                        keep_crease_vertices=self.keep_crease_vertices)
                with fitted:
                    pos = fitted.positions
            if cage_obj.mode == 'EDIT':
                raise ValueError("leave edit mode on the cage first")
            meshio.write_positions(cage_obj, pos)
            rms = report.passes[-1].rms_rel if report.passes else float("nan")
            cage_obj["cagekit_fit_rms_rel"] = float(rms)
            self.report({'INFO'}, "CageKit: fitted in %d passes (rms %.2g of the diagonal)"
                        % (len(report.passes) - 1, rms))
            return {'FINISHED'}
        except Exception as e:  # cagekit errors, ImportError of the library, bad input
            return _fail(self, e)
        finally:
            progress.end()


class CAGEKIT_OT_bind(bpy.types.Operator):
    """Bind a scan to the active cage: the scan then follows edits of the cage live"""

    bl_idname = "cagekit.bind"
    bl_label = "Bind Scan to Cage"
    bl_options = {'REGISTER'}

    scan: StringProperty(name="Scan", default="",
                         description="Scan object (empty: the cage's scan, or the other selected mesh)")
    local_frame: BoolProperty(name="Local Frame", default=False,
                              description="Keep the whole offset in the surface's frame (else along the normal)")

    @classmethod
    def poll(cls, context):
        return _active_mesh(context)

    def execute(self, context):
        cage_obj = context.active_object
        progress = _Progress(context)
        try:
            scan = _cage_and_scan(context, cage_obj, self.scan)
            ck = sdk()
            ctx = ck.Context(progress=progress)
            matrix = _relative(scan, cage_obj)
            rest_scan = meshio.positions(scan)
            with meshio.scan_mesh(scan, context=ctx) as mesh, \
                    meshio.cage_from_object(cage_obj, matrix, context=ctx) as cage:
                binding = ck.bind(cage, mesh, mode="local_frame" if self.local_frame else "normal")
            try:
                deformer = ck.CpuDeformer(binding)
                control = binding.control_points()
                rest_deformed, _ = deformer.deform(control, normals=False)
            except BaseException:
                binding.close()
                raise
            handlers.add(handlers.Bound(scan.name, cage_obj.name, binding, deformer, matrix, control,
                                        rest_deformed, rest_scan))
            scan["cagekit_cage"] = cage_obj.name
            self.report({'INFO'}, "CageKit: %r follows edits of %r (%d vertices, %d control points)"
                        % (scan.name, cage_obj.name, len(rest_scan), len(control)))
            return {'FINISHED'}
        except Exception as e:  # cagekit errors, ImportError of the library, bad input
            return _fail(self, e)
        finally:
            progress.end()


class CAGEKIT_OT_unbind(bpy.types.Operator):
    """End the live bindings of the active object (as scan or as cage)"""

    bl_idname = "cagekit.unbind"
    bl_label = "Unbind"
    bl_options = {'REGISTER'}

    @classmethod
    def poll(cls, context):
        return context.active_object is not None

    def execute(self, context):
        count = handlers.remove_for_object(context.active_object.name)
        if count == 0:
            self.report({'WARNING'}, "CageKit: %r has no live binding" % context.active_object.name)
            return {'CANCELLED'}
        self.report({'INFO'}, "CageKit: %d binding(s) ended" % count)
        return {'FINISHED'}


classes = (CAGEKIT_OT_scan_to_cage, CAGEKIT_OT_fit, CAGEKIT_OT_bind, CAGEKIT_OT_unbind)
