# SPDX-License-Identifier: GPL-3.0-or-later
"""CageKit for Blender: structure-preserving Catmull-Clark cages from scans.

Operators (View3D > Object > CageKit, and the sidebar's CageKit tab):
  cagekit.scan_to_cage  active mesh -> fitted cage object with creases and a Subdivision Surface modifier
  cagekit.fit           fit the active cage to a scan
  cagekit.bind          the scan follows later edits of the cage live (CPU deformer)
  cagekit.unbind        end it
scan_to_cage, fit and bind run their SDK work on a worker thread when clicked (Esc / right-click
cancels); from scripts and in background mode they run synchronously (operators.py).
The SDK is the `cagekit` Python package over libcagekit (ctypes), bundled in the add-on zip.
"""

bl_info = {
    "name": "CageKit",
    "author": "CageKit authors",
    "version": (0, 2, 0),
    "blender": (3, 4, 0),
    "location": "View3D > Object > CageKit; View3D > Sidebar > CageKit",
    "description": "Structure-preserving Catmull-Clark cages from scans: simplify, fit, live multiresolution editing",
    "category": "Mesh",
}

if "bpy" in locals():  # script reload
    import importlib
    importlib.reload(meshio)      # noqa: F821
    importlib.reload(handlers)    # noqa: F821
    importlib.reload(operators)   # noqa: F821

import bpy

from . import handlers, meshio, operators


class CAGEKIT_MT_object(bpy.types.Menu):
    bl_idname = "CAGEKIT_MT_object"
    bl_label = "CageKit"

    def draw(self, context):
        layout = self.layout
        layout.operator(operators.CAGEKIT_OT_scan_to_cage.bl_idname)
        layout.operator(operators.CAGEKIT_OT_fit.bl_idname)
        layout.operator(operators.CAGEKIT_OT_bind.bl_idname)
        layout.operator(operators.CAGEKIT_OT_unbind.bl_idname)


class CAGEKIT_PT_panel(bpy.types.Panel):
    bl_idname = "CAGEKIT_PT_panel"
    bl_label = "CageKit"
    bl_space_type = 'VIEW_3D'
    bl_region_type = 'UI'
    bl_category = "CageKit"

    def draw(self, context):
        layout = self.layout
        if operators.running_jobs:
            box = layout.box()
            for job in operators.running_jobs:
                box.label(text="%s: %s %d%%" % (job.name, job.stage or "starting", int(100 * job.fraction)),
                          icon='SORTTIME')
            box.operator(operators.CAGEKIT_OT_cancel_jobs.bl_idname, text="Cancel", icon='CANCEL')
        settings = getattr(context.scene, "cagekit", None)
        if settings is not None:
            operators.draw_scan_to_cage_options(layout.box(), settings)
        col = layout.column(align=True)
        col.operator(operators.CAGEKIT_OT_scan_to_cage.bl_idname, icon='MOD_SUBSURF')
        col.operator(operators.CAGEKIT_OT_fit.bl_idname)
        col.operator(operators.CAGEKIT_OT_bind.bl_idname, icon='LINKED')
        col.operator(operators.CAGEKIT_OT_unbind.bl_idname, icon='UNLINKED')
        bound = handlers.bindings()
        if bound:
            box = layout.box()
            for scan, entry in bound.items():
                box.label(text="%s follows %s" % (scan, entry.cage_name), icon='LINKED')


def _menu(self, context):
    self.layout.menu(CAGEKIT_MT_object.bl_idname)


_classes = operators.classes + (CAGEKIT_MT_object, CAGEKIT_PT_panel)


def register():
    for cls in _classes:
        bpy.utils.register_class(cls)
    bpy.types.Scene.cagekit = bpy.props.PointerProperty(type=operators.CageKitSettings)
    bpy.types.VIEW3D_MT_object.append(_menu)
    handlers.register()


def unregister():
    handlers.unregister()
    bpy.types.VIEW3D_MT_object.remove(_menu)
    del bpy.types.Scene.cagekit
    for cls in reversed(_classes):
        bpy.utils.unregister_class(cls)
