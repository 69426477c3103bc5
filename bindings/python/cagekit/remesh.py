# SPDX-License-Identifier: GPL-3.0-or-later
"""Remeshing a triangle mesh into a quad-dominant cage (cagekit_mesh_remesh).

    cage, report = cagekit.remesh(mesh, method="anisotropic", tolerance=0.002)
    cage, report = cagekit.remesh(mesh, method="quad", edge_length=0.10, regions=30, weights=(500, 500, 500))
    report.faces, report.quads, report.valence4_vertices, report.min_scaled_jacobian

Method "anisotropic" (thesis ch. 5): curvature-line remeshing; edges on feature lines are tagged
as infinitely sharp creases in the returned Cage. Long operation (progress stages "curvature
field", "curvature lines", "meshing"; cancel); the GIL is released for the whole call.
Method "quad" (thesis ch. 6): two-step quad-dominant remeshing: `regions` VSA regions (0: by
`region_tolerance`), boundary samples `edge_length` (relative to the bbox diagonal) apart,
`weights` = (w_tri, w_PT, w_T) of Table 6.1; region boundaries sharper than
`feature_angle_degrees` are tagged as creases (progress stages "vsa segmentation", "remesh
constraints", "quad region selection", "post-processing"; cancel).

The C declarations of this part of the header are made here and added to _lib.PROTOTYPES and
_lib.STRUCTS, so that tests/test_abi.py checks them with the rest.
"""
import ctypes
import enum
from ctypes import POINTER, c_double, c_size_t, c_uint32, c_uint64, c_void_p

from . import _lib
from ._records import enum_value as _enum, from_struct
from .cage import Cage


class RemeshMethod(enum.IntEnum):
    ANISOTROPIC = 0  # curvature-line remeshing (thesis ch. 5)
    QUAD = 1         # two-step quad-dominant remeshing (thesis ch. 6)


# --- declarations (include/cagekit/cagekit.h, "remeshing") ---------------------------------------
class RemeshOptions(_lib._Versioned):
    _fields_ = [("struct_size", c_size_t), ("method", _lib.c_enum), ("tolerance", c_double),
                ("feature_angle_degrees", c_double), ("max_face_valence", c_uint32), ("threads", c_uint32),
                ("curvature_radius", c_double), ("edge_length", c_double), ("regions", c_uint32),
                ("region_tolerance", c_double), ("triangle_weight", c_double), ("pentagon_weight", c_double),
                ("t_joint_weight", c_double), ("refinement_passes", c_uint32), ("seed_faces", c_void_p),
                ("seed_face_count", c_uint32), ("pinned_region_count", c_uint32),
                ("pinned_region_offsets", c_void_p), ("pinned_faces", c_void_p)]
    _defaults = {"method": 0, "tolerance": 0.002, "feature_angle_degrees": 40.0, "max_face_valence": 5,
                 "threads": 0, "curvature_radius": 0.01, "edge_length": 0.05, "regions": 30, "region_tolerance": 0.01,
                 "triangle_weight": 40.0, "pentagon_weight": 40.0, "t_joint_weight": 100.0, "refinement_passes": 1,
                 "seed_faces": None, "seed_face_count": 0, "pinned_region_count": 0, "pinned_region_offsets": None,
                 "pinned_faces": None}


class RemeshReport(_lib._Versioned):
    _fields_ = [("struct_size", c_size_t), ("faces", c_uint64), ("vertices", c_uint64), ("quads", c_uint64),
                ("interior_vertices", c_uint64), ("valence4_vertices", c_uint64), ("max_face_valence", c_uint32),
                ("max_vertex_valence", c_uint32), ("creases", c_uint64), ("regions", c_uint64), ("lines", c_uint64),
                ("holes", c_uint64), ("mean_alignment_deg", c_double), ("min_scaled_jacobian", c_double),
                ("seconds", c_double), ("requested_regions", c_uint64), ("split_regions", c_uint64),
                ("merged_regions", c_uint64), ("layout_retries", c_uint64),
                ("mended_faces", c_uint64), ("partitioned_regions", c_uint64)]


_lib.STRUCTS.update({"cagekit_remesh_options": RemeshOptions, "cagekit_remesh_report": RemeshReport})
_lib.PROTOTYPES.update({
    "cagekit_mesh_remesh": (_lib.c_status, [c_void_p, POINTER(RemeshOptions), POINTER(c_void_p),
                                            POINTER(RemeshReport)]),
})
_lib._declare(_lib.lib)  # ImportError naming the function when the loaded library lacks one


def remesh(mesh, method=RemeshMethod.ANISOTROPIC, tolerance=0.002, feature_angle_degrees=40.0, max_face_valence=5,
           threads=0, curvature_radius=0.01, edge_length=0.05, regions=30, region_tolerance=0.01,
           weights=(40.0, 40.0, 100.0), refinement_passes=1, seed_faces=None, pinned_regions=None):
    """Remeshes `mesh` (an oriented 2-manifold Mesh; polygons are fan-triangulated first) into a
    new Cage with crease tags on feature lines (anisotropic) or sharp region boundaries (quad).
    Returns (cage, report); the report holds faces, vertices, quads, interior_vertices,
    valence4_vertices, max_face_valence, max_vertex_valence, creases, regions, lines, holes,
    mean_alignment_deg, min_scaled_jacobian, seconds and (quad) requested_regions, split_regions,
    merged_regions, layout_retries, mended_faces, partitioned_regions. Option values as the C API's
    cagekit_remesh_options (method also as a name; weights = (triangle_weight, pentagon_weight,
    t_joint_weight)). Quad only: `seed_faces` (face ids that each start a region) and
    `pinned_regions` (a list of face-id lists, each a region the segmentation keeps as it is;
    counted in `regions`)."""
    if len(weights) != 3:
        raise ValueError("weights must be (triangle, pentagon, t_joint)")
    # ctypes arrays (no numpy needed here); alive until the call returns.
    seeds = (c_uint32 * len(seed_faces or []))(*[int(f) for f in (seed_faces or [])])
    pinned = [[int(f) for f in region] for region in (pinned_regions or [])]
    offsets = (c_uint32 * (len(pinned) + 1))()
    for k, region in enumerate(pinned):
        offsets[k + 1] = offsets[k] + len(region)
    pinned_faces = (c_uint32 * offsets[len(pinned)])(*[f for region in pinned for f in region])
    options = RemeshOptions.new(method=int(_enum(RemeshMethod, method)), tolerance=float(tolerance),
                                feature_angle_degrees=float(feature_angle_degrees),
                                max_face_valence=int(max_face_valence), threads=int(threads),
                                curvature_radius=float(curvature_radius), edge_length=float(edge_length),
                                regions=int(regions), region_tolerance=float(region_tolerance),
                                triangle_weight=float(weights[0]), pentagon_weight=float(weights[1]),
                                t_joint_weight=float(weights[2]), refinement_passes=int(refinement_passes),
                                seed_face_count=len(seeds), pinned_region_count=len(pinned))
    if len(seeds):
        options.seed_faces = ctypes.cast(seeds, c_void_p)
    if pinned:
        options.pinned_region_offsets = ctypes.cast(offsets, c_void_p)
        options.pinned_faces = ctypes.cast(pinned_faces, c_void_p)
    report = RemeshReport.new()
    out = ctypes.c_void_p()
    mesh._context._call(_lib.lib.cagekit_mesh_remesh, mesh._handle, ctypes.byref(options), ctypes.byref(out),
                        ctypes.byref(report), outs=[(out, Cage._release_name)])
    return Cage._wrap(out.value, mesh._context), from_struct(report, "RemeshReport")
