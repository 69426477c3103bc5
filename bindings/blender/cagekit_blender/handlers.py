# SPDX-License-Identifier: GPL-3.0-or-later
"""Live binding: a scan follows edits of its cage through CageKit's CPU deformer.

A module-level registry maps each bound scan object (by name) to its cage object, deformer and
rest state. One depsgraph_update_post handler, registered while any binding exists, looks for
geometry updates of a bound cage; for each it reads the cage's vertices (from the edit-mode bmesh
while the cage is edited), brings them into the scan's local space with the matrix of bind time,
runs the deformer (incrementally when few control points moved) and writes the scan's vertices:

    scan = scan at bind time + (deform(cage now) - deform(cage at bind time))

so an unedited cage leaves the scan exactly as it was. Writing the scan triggers another depsgraph
update; a re-entrancy flag and the "did any control point move" test stop the recursion. Bindings
live in memory only: they end with unbind, with the add-on's unregister and when a file is loaded.
"""
import bpy
import numpy as np
from bpy.app.handlers import persistent

from . import meshio


class Bound:
    def __init__(self, scan_name, cage_name, binding, deformer, matrix, control, rest_deformed, rest_scan):
        self.scan_name = scan_name
        self.cage_name = cage_name
        self.binding = binding
        self.deformer = deformer
        self.matrix = matrix              # cage local -> scan local, fixed at bind time
        self.control = control            # last control points handed to the deformer
        self.rest_deformed = rest_deformed
        self.rest_scan = rest_scan
        self.updates = 0                  # deformer runs since bind (the tests read it)
        self.last_error = None

    def close(self):
        for h in (self.deformer, self.binding):
            try:
                h.close()
            except Exception:
                pass


_bound = {}      # scan object name -> Bound
_busy = False


def bindings():
    return dict(_bound)


def add(entry):
    remove(entry.scan_name)
    _bound[entry.scan_name] = entry
    if on_depsgraph_update not in bpy.app.handlers.depsgraph_update_post:
        bpy.app.handlers.depsgraph_update_post.append(on_depsgraph_update)


def remove(scan_name):
    entry = _bound.pop(scan_name, None)
    if entry is not None:
        entry.close()
    if not _bound:
        _remove_handler()
    return entry


def remove_for_object(name):
    """Ends every binding whose scan or cage is the object `name`; returns how many."""
    names = [s for s, e in _bound.items() if s == name or e.cage_name == name]
    for s in names:
        remove(s)
    return len(names)


def clear():
    for s in list(_bound):
        remove(s)
    _remove_handler()


def _remove_handler():
    while on_depsgraph_update in bpy.app.handlers.depsgraph_update_post:
        bpy.app.handlers.depsgraph_update_post.remove(on_depsgraph_update)


def follow(entry, control):
    """Deforms entry's scan for `control` ((C, 3) points in scan space); False if unchanged."""
    moved = np.nonzero(np.any(control != entry.control, axis=1))[0]
    if len(moved) == 0:
        return False
    if len(moved) * 4 < len(control):
        deformed, _ = entry.deformer.update(control, moved, normals=False, copy=False)
    else:
        deformed, _ = entry.deformer.deform(control, normals=False, copy=False)
    entry.control = control
    scan = bpy.data.objects.get(entry.scan_name)
    if scan is None or scan.type != 'MESH' or len(scan.data.vertices) != len(entry.rest_scan):
        entry.last_error = "scan object %r is gone or changed its vertex count" % entry.scan_name
        return False
    meshio.write_positions(scan, entry.rest_scan + (deformed - entry.rest_deformed))
    entry.updates += 1
    return True


def _cage_control(entry, cage):
    pos = meshio.edit_positions(cage)
    if len(pos) != len(entry.control):
        entry.last_error = "cage %r has %d vertices, the binding %d: edits that change the topology " \
                           "cannot drive the scan" % (cage.name, len(pos), len(entry.control))
        return None
    return meshio.transform(entry.matrix, pos)


@persistent
def on_depsgraph_update(scene, depsgraph):
    global _busy
    if _busy or not _bound:
        return
    changed_objects, changed_meshes = set(), set()
    for update in depsgraph.updates:
        if not update.is_updated_geometry:
            continue
        data = update.id.original if update.id is not None else None
        if isinstance(data, bpy.types.Object):
            changed_objects.add(data.name)
        elif isinstance(data, bpy.types.Mesh):
            changed_meshes.add(data.name)
    if not changed_objects and not changed_meshes:
        return
    _busy = True
    try:
        for entry in list(_bound.values()):
            cage = bpy.data.objects.get(entry.cage_name)
            if cage is None or cage.type != 'MESH':
                continue
            if entry.cage_name not in changed_objects and cage.data.name not in changed_meshes:
                continue
            scan = bpy.data.objects.get(entry.scan_name)
            if scan is None or scan.mode == 'EDIT':
                continue
            try:
                control = _cage_control(entry, cage)
                if control is not None:
                    follow(entry, control)
            except Exception as e:  # a handler must never raise into Blender
                entry.last_error = str(e)
                print("cagekit: live binding of %r: %s" % (entry.scan_name, e))
    finally:
        _busy = False


@persistent
def on_load_pre(*_args):
    clear()


@persistent
def on_undo_post(*_args):
    """Undo of a bind (the scan's 'cagekit_cage' property is gone with it) ends the binding."""
    for scan_name, entry in list(_bound.items()):
        scan = bpy.data.objects.get(scan_name)
        if scan is None or scan.get("cagekit_cage") != entry.cage_name:
            remove(scan_name)


def register():
    if on_load_pre not in bpy.app.handlers.load_pre:
        bpy.app.handlers.load_pre.append(on_load_pre)
    if on_undo_post not in bpy.app.handlers.undo_post:
        bpy.app.handlers.undo_post.append(on_undo_post)


def unregister():
    clear()
    while on_load_pre in bpy.app.handlers.load_pre:
        bpy.app.handlers.load_pre.remove(on_load_pre)
    while on_undo_post in bpy.app.handlers.undo_post:
        bpy.app.handlers.undo_post.remove(on_undo_post)
