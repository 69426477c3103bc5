# SPDX-License-Identifier: GPL-3.0-or-later
"""Blender meshes <-> numpy arrays and cagekit objects.

Crease values: Blender hands an edge crease c in [0, 1] to OpenSubdiv as sharpness 10 * c^2
(measured in Blender 3.4: a crease of 0.3 subdivides exactly as CageKit's sharpness 0.9, not 3.0),
so CageKit's sharpness s becomes the crease sqrt(min(s, 10) / 10) and CageKit's infinitely sharp
tag (SHARP = 10) the crease 1.0. Vertex creases (CageKit corners) use the same rule.
"""
import bpy
import numpy as np

from ._sdk import sdk


def crease_from_sharpness(sharpness):
    return np.sqrt(np.clip(np.asarray(sharpness, dtype=np.float64), 0.0, 10.0) / 10.0).astype(np.float32)


def sharpness_from_crease(crease):
    c = np.clip(np.asarray(crease, dtype=np.float64), 0.0, 1.0)
    return (10.0 * c * c).astype(np.float32)


def _mesh(obj):
    if obj.mode == 'EDIT':
        obj.update_from_editmode()
    return obj.data


def positions(obj):
    """(N, 3) float64 local coordinates of the object's own mesh (no modifiers)."""
    me = _mesh(obj)
    co = np.empty(len(me.vertices) * 3, dtype=np.float32)
    me.vertices.foreach_get("co", co)
    return co.reshape(-1, 3).astype(np.float64)


def edit_positions(obj):
    """Local coordinates, read from the edit-mode bmesh while obj is in edit mode."""
    if obj.mode != 'EDIT':
        return positions(obj)
    import bmesh
    bm = bmesh.from_edit_mesh(obj.data)
    return np.array([v.co[:] for v in bm.verts], dtype=np.float64).reshape(-1, 3)


def write_positions(obj, pos):
    me = obj.data
    me.vertices.foreach_set("co", np.ascontiguousarray(pos, dtype=np.float32).ravel())
    me.update()


def faces(obj):
    """(face_sizes, flat vertex indices) uint32 arrays of the object's polygons."""
    me = _mesh(obj)
    n = len(me.polygons)
    start = np.empty(n, dtype=np.int64)
    total = np.empty(n, dtype=np.int64)
    tmp = np.empty(n, dtype=np.int32)
    me.polygons.foreach_get("loop_start", tmp)
    start[:] = tmp
    me.polygons.foreach_get("loop_total", tmp)
    total[:] = tmp
    loops = np.empty(len(me.loops), dtype=np.int32)
    me.loops.foreach_get("vertex_index", loops)
    offsets = np.repeat(start - np.concatenate(([0], np.cumsum(total)[:-1])), total)
    flat = loops[np.arange(int(total.sum())) + offsets] if n else np.empty(0, dtype=np.int32)
    return total.astype(np.uint32), flat.astype(np.uint32)


def edge_pairs(me):
    ev = np.empty(len(me.edges) * 2, dtype=np.int32)
    me.edges.foreach_get("vertices", ev)
    return ev.reshape(-1, 2)


def _edge_crease_uses_attribute():
    return "crease" not in bpy.types.MeshEdge.bl_rna.properties  # Blender 4.0+: 'crease_edge'


def edge_creases(me):
    if _edge_crease_uses_attribute():
        attr = me.attributes.get("crease_edge")
        values = np.zeros(len(me.edges), dtype=np.float32)
        if attr is not None:
            attr.data.foreach_get("value", values)
        return values
    values = np.empty(len(me.edges), dtype=np.float32)
    me.edges.foreach_get("crease", values)
    return values


def set_edge_creases(me, values):
    values = np.ascontiguousarray(values, dtype=np.float32)
    if _edge_crease_uses_attribute():
        attr = me.attributes.get("crease_edge") or me.attributes.new("crease_edge", 'FLOAT', 'EDGE')
        attr.data.foreach_set("value", values)
    else:
        me.edges.foreach_set("crease", values)


def vertex_creases(me):
    values = np.zeros(len(me.vertices), dtype=np.float32)
    attr = me.attributes.get("crease_vert") if hasattr(me, "attributes") else None
    if attr is not None and attr.domain == 'POINT':
        attr.data.foreach_get("value", values)
    elif len(getattr(me, "vertex_creases", ())):            # Blender 3.x layer
        me.vertex_creases[0].data.foreach_get("value", values)
    return values


def set_vertex_creases(me, indices, values):
    """Vertex creases on `indices` (others 0)."""
    full = np.zeros(len(me.vertices), dtype=np.float32)
    full[np.asarray(indices, dtype=np.int64)] = values
    if _edge_crease_uses_attribute():
        attr = me.attributes.get("crease_vert") or me.attributes.new("crease_vert", 'FLOAT', 'POINT')
        attr.data.foreach_set("value", full)
        return
    import bmesh                                             # Blender 3.x: the bmesh crease layer
    bm = bmesh.new()
    bm.from_mesh(me)
    layer = bm.verts.layers.crease.verify()
    bm.verts.ensure_lookup_table()
    for i, v in enumerate(bm.verts):
        v[layer] = float(full[i])
    bm.to_mesh(me)
    bm.free()


def scan_mesh(obj, matrix=None, context=None):
    """cagekit.Mesh of the object's vertices and polygons (matrix: 4x4 applied to the vertices)."""
    ck = sdk()
    pos = positions(obj)
    if matrix is not None:
        pos = transform(matrix, pos)
    sizes, flat = faces(obj)
    return ck.Mesh.from_arrays(pos, (sizes, flat), context=context)


def transform(matrix, pos):
    m = np.array(matrix, dtype=np.float64).reshape(4, 4)
    return pos @ m[:3, :3].T + m[:3, 3]


def cage_arrays(obj, matrix=None, boundary_rule=None):
    """Keyword arguments of cagekit.Cage.from_arrays for a Blender mesh object (numpy arrays only,
    read on the main thread; the Cage can then be made on any thread): polygons, edge creases ->
    crease tags (boundary edges: sharp), vertex creases -> corner tags (sharpness 10 c^2)."""
    ck = sdk()
    me = _mesh(obj)
    pos = positions(obj)
    if matrix is not None:
        pos = transform(matrix, pos)
    sizes, flat = faces(obj)
    crease = edge_creases(me)
    # boundary edges carry no Blender crease (see write_cage_into_mesh); they are tagged sharp
    # again, as the SDK's cages have them (no change to the surface, but the fit sees them)
    crease[edge_face_counts(me) < 2] = 1.0
    tagged = np.nonzero(crease > 0)[0]
    corners = vertex_creases(me)
    tagged_corners = np.nonzero(corners > 0)[0]
    if boundary_rule is None:
        boundary_rule = ck.BoundaryRule.EDGES_ONLY
        for mod in obj.modifiers:
            if mod.type == 'SUBSURF' and mod.boundary_smooth == 'PRESERVE_CORNERS':
                boundary_rule = ck.BoundaryRule.EDGES_AND_CORNERS
    return dict(
        positions=pos, faces=(sizes, flat),
        creases=edge_pairs(me)[tagged].astype(np.uint32), crease_sharpness=sharpness_from_crease(crease[tagged]),
        corners=tagged_corners.astype(np.uint32) if len(tagged_corners) else None,
        corner_sharpness=sharpness_from_crease(corners[tagged_corners]) if len(tagged_corners) else None,
        boundary_rule=boundary_rule)


def cage_from_object(obj, matrix=None, context=None, boundary_rule=None):
    """cagekit.Cage from a Blender mesh object (see cage_arrays)."""
    return sdk().Cage.from_arrays(context=context, **cage_arrays(obj, matrix, boundary_rule))


def new_mesh(name, pos, sizes, flat):
    """A new bpy mesh with the given vertices and polygons (vertex order kept)."""
    me = bpy.data.meshes.new(name)
    sizes = np.asarray(sizes, dtype=np.int32)
    me.vertices.add(len(pos))
    me.vertices.foreach_set("co", np.ascontiguousarray(pos, dtype=np.float32).ravel())
    me.loops.add(int(sizes.sum()))
    me.loops.foreach_set("vertex_index", np.ascontiguousarray(flat, dtype=np.int32))
    me.polygons.add(len(sizes))
    starts = np.concatenate(([0], np.cumsum(sizes)[:-1])).astype(np.int32)
    me.polygons.foreach_set("loop_start", starts)
    if "loop_total" in bpy.types.MeshPolygon.bl_rna.properties and \
            not bpy.types.MeshPolygon.bl_rna.properties["loop_total"].is_readonly:
        me.polygons.foreach_set("loop_total", sizes)
    me.update(calc_edges=True)
    me.validate(verbose=False)
    return me


def edge_face_counts(me):
    loops = np.empty(len(me.loops), dtype=np.int32)
    me.loops.foreach_get("edge_index", loops)
    return np.bincount(loops, minlength=len(me.edges))


def write_cage_into_mesh(me, cage):
    """Creases and corners of `cage` (cagekit.Cage with the mesh's vertex numbering) onto the
    mesh's edges and vertices. Returns (edges creased, corners set, two-crease vertices)
    (write_cage_tags_into_mesh)."""
    return write_cage_tags_into_mesh(me, cage.creases, cage.corners)


def write_cage_tags_into_mesh(me, creases, corners):
    """Crease tags (pairs, sharpness) and corner tags (vertices, sharpness), as Cage.creases and
    Cage.corners give them, onto the mesh's edges and vertices. Returns (edges creased, corners
    set, two-crease vertices).

    Crease tags on boundary edges are not written: OpenSubdiv makes boundary edges infinitely
    sharp anyway, and Blender adds the smaller crease of the two edges of a valence-2 vertex to
    that vertex's sharpness (so that a plane with sharp edges keeps sharp corners), which
    would turn the cage's valence-2 boundary vertices into corners that CageKit does not have.
    Interior vertices with exactly two edges, both creased, get the same treatment from Blender
    and cannot be avoided: they are counted and returned."""
    pairs, sharp = creases
    ev = np.sort(edge_pairs(me).astype(np.int64), axis=1)
    n = max(len(me.vertices), 1)
    keys = ev[:, 0] * n + ev[:, 1]
    order = np.argsort(keys)
    values = np.zeros(len(me.edges), dtype=np.float32)
    if len(pairs):
        p = np.sort(pairs.astype(np.int64), axis=1)
        want = p[:, 0] * n + p[:, 1]
        pos = np.searchsorted(keys[order], want)
        pos = np.clip(pos, 0, len(order) - 1)
        found = keys[order][pos] == want
        values[order[pos[found]]] = crease_from_sharpness(sharp[found])
    values[edge_face_counts(me) < 2] = 0.0
    set_edge_creases(me, values)
    verts, vsharp = corners
    if len(verts):
        set_vertex_creases(me, verts, crease_from_sharpness(vsharp))
    edges = edge_pairs(me)
    valence = np.bincount(edges.ravel(), minlength=len(me.vertices))
    creased_valence = np.bincount(edges[values > 0].ravel(), minlength=len(me.vertices))
    two_crease = int(np.count_nonzero((valence == 2) & (creased_valence == 2)))
    return int(np.count_nonzero(values)), len(verts), two_crease
