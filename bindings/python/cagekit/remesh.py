# SPDX-License-Identifier: GPL-3.0-or-later
"""Remeshing a triangle mesh into a quad-dominant cage: one function per remesher, as in the C API.

    cage, report = cagekit.remesh_anisotropic(mesh, tolerance=0.002)
    cage, report = cagekit.remesh_quad(mesh, edge_length=0.10, regions=30, weights=(500, 500, 500))
    report.faces, report.quads, report.valence4_vertices, report.min_scaled_jacobian

remesh_anisotropic (cagekit_mesh_remesh_anisotropic, thesis ch. 5): curvature-line remeshing;
edges on feature lines are tagged as infinitely sharp creases in the returned Cage. Long operation
(progress stages "curvature field", "curvature lines", "meshing"; cancel); the GIL is released for
the whole call.
remesh_quad (cagekit_mesh_remesh_quad, thesis ch. 6): two-step quad-dominant remeshing: `regions`
VSA regions (0: by `region_tolerance`), boundary samples `edge_length` (relative to the bbox
diagonal) apart, `weights` = (w_tri, w_PT, w_T) of Table 6.1; region boundaries sharper than
`crease_angle_degrees` are tagged as creases (progress stages "vsa segmentation", "remesh
constraints", "quad region selection", "post-processing"; cancel).

The C declarations of this part of the header are made here, in this module's STRUCTS and
PROTOTYPES and on its own function objects (`lib`, a _lib.Functions), which change nothing in
_lib; tests/test_abi.py checks them with the rest. Keyword defaults come from the structs'
defaults (CAGEKIT_*_INIT, written once).
"""
from __future__ import annotations

import ctypes
from ctypes import POINTER, c_double, c_size_t, c_uint32, c_uint64, c_void_p
from typing import Any, Iterable, Optional, Sequence, Tuple

from . import _lib
from ._numpy import npt
from ._records import Record, from_struct
from .cage import Cage
from .mesh import Mesh


# --- declarations (include/cagekit/cagekit.h, "remeshing") ---------------------------------------
class RemeshQuality(ctypes.Structure):
    _fields_ = [("faces", c_uint64), ("vertices", c_uint64), ("quads", c_uint64), ("interior_vertices", c_uint64),
                ("valence4_vertices", c_uint64), ("max_face_valence", c_uint32), ("max_vertex_valence", c_uint32),
                ("creases", c_uint64), ("min_scaled_jacobian", c_double), ("seconds", c_double)]


class AnisotropicOptions(_lib._Versioned):
    _fields_ = [("struct_size", c_size_t), ("tolerance", c_double), ("feature_angle_degrees", c_double),
                ("max_face_valence", c_uint32), ("threads", c_uint32), ("curvature_radius", c_double),
                ("sharp_edges", c_void_p), ("sharp_edge_count", c_uint32)]
    _defaults = {"tolerance": 0.002, "feature_angle_degrees": 40.0, "max_face_valence": 5, "threads": 0,
                 "curvature_radius": 0.01, "sharp_edges": None, "sharp_edge_count": 0}


class AnisotropicReport(_lib._Versioned):
    _fields_ = [("struct_size", c_size_t), ("quality", RemeshQuality), ("regions", c_uint64), ("lines", c_uint64),
                ("holes", c_uint64), ("mean_alignment_deg", c_double)]


class QuadRemeshOptions(_lib._Versioned):
    _fields_ = [("struct_size", c_size_t), ("edge_length", c_double), ("regions", c_uint32),
                ("region_tolerance", c_double), ("crease_angle_degrees", c_double), ("triangle_weight", c_double),
                ("pentagon_weight", c_double), ("t_joint_weight", c_double), ("refinement_passes", c_uint32),
                ("threads", c_uint32), ("seed_faces", c_void_p), ("seed_face_count", c_uint32),
                ("pinned_region_count", c_uint32), ("pinned_region_offsets", c_void_p), ("pinned_faces", c_void_p),
                ("sharp_edges", c_void_p), ("sharp_edge_count", c_uint32)]
    _defaults = {"edge_length": 0.05, "regions": 30, "region_tolerance": 0.01, "crease_angle_degrees": 40.0,
                 "triangle_weight": 40.0, "pentagon_weight": 40.0, "t_joint_weight": 100.0, "refinement_passes": 1,
                 "threads": 0, "seed_faces": None, "seed_face_count": 0, "pinned_region_count": 0,
                 "pinned_region_offsets": None, "pinned_faces": None, "sharp_edges": None, "sharp_edge_count": 0}


class QuadRemeshReport(_lib._Versioned):
    _fields_ = [("struct_size", c_size_t), ("quality", RemeshQuality), ("regions", c_uint64), ("arcs", c_uint64),
                ("requested_regions", c_uint64), ("split_regions", c_uint64), ("merged_regions", c_uint64),
                ("layout_retries", c_uint64), ("mended_faces", c_uint64), ("partitioned_regions", c_uint64),
                ("reseeded_regions", c_uint64)]


STRUCTS = {"cagekit_remesh_quality": RemeshQuality, "cagekit_anisotropic_options": AnisotropicOptions,
           "cagekit_anisotropic_report": AnisotropicReport, "cagekit_quad_remesh_options": QuadRemeshOptions,
           "cagekit_quad_remesh_report": QuadRemeshReport}
PROTOTYPES = {
    "cagekit_mesh_remesh_anisotropic": (_lib.c_status, [c_void_p, POINTER(AnisotropicOptions), POINTER(c_void_p),
                                                        POINTER(AnisotropicReport)]),
    "cagekit_mesh_remesh_quad": (_lib.c_status, [c_void_p, POINTER(QuadRemeshOptions), POINTER(c_void_p),
                                                 POINTER(QuadRemeshReport)]),
}
lib = _lib.Functions(PROTOTYPES)  # ImportError naming the function when the loaded library lacks one

# CAGEKIT_ANISOTROPIC_OPTIONS_INIT and CAGEKIT_QUAD_REMESH_OPTIONS_INIT, written once (in the structs).
_A = AnisotropicOptions.defaults()
_Q = QuadRemeshOptions.defaults()
_WEIGHTS = (_Q["triangle_weight"], _Q["pentagon_weight"], _Q["t_joint_weight"])


def quad_options(edge_length: float = _Q["edge_length"], regions: int = _Q["regions"],
                 region_tolerance: float = _Q["region_tolerance"],
                 crease_angle_degrees: float = _Q["crease_angle_degrees"], weights: Sequence[float] = _WEIGHTS,
                 refinement_passes: int = _Q["refinement_passes"], threads: int = _Q["threads"],
                 seed_faces: Optional[Sequence[int]] = None, pinned_regions: Optional[Sequence[Iterable[int]]] = None,
                 sharp_edges: Optional[npt.ArrayLike] = None) -> Tuple[QuadRemeshOptions, Any]:
    """A QuadRemeshOptions (cagekit_quad_remesh_options) from remesh_quad's keyword arguments, and the
    ctypes arrays it points to (keep them alive until the call returns)."""
    if len(weights) != 3:
        raise ValueError("weights must be (triangle, pentagon, t_joint)")
    # ctypes arrays (no numpy needed here).
    seeds = (c_uint32 * len(seed_faces or []))(*[int(f) for f in (seed_faces or [])])
    pinned = [[int(f) for f in region] for region in (pinned_regions or [])]
    offsets = (c_uint32 * (len(pinned) + 1))()
    for k, region in enumerate(pinned):
        offsets[k + 1] = offsets[k] + len(region)
    pinned_faces = (c_uint32 * offsets[len(pinned)])(*[f for region in pinned for f in region])
    options = QuadRemeshOptions.new(edge_length=float(edge_length), regions=int(regions),
                                    region_tolerance=float(region_tolerance),
                                    crease_angle_degrees=float(crease_angle_degrees),
                                    triangle_weight=float(weights[0]), pentagon_weight=float(weights[1]),
                                    t_joint_weight=float(weights[2]), refinement_passes=int(refinement_passes),
                                    threads=int(threads), seed_face_count=len(seeds), pinned_region_count=len(pinned))
    if len(seeds):
        options.seed_faces = ctypes.cast(seeds, c_void_p)
    if pinned:
        options.pinned_region_offsets = ctypes.cast(offsets, c_void_p)
        options.pinned_faces = ctypes.cast(pinned_faces, c_void_p)
    sharp = _lib.set_sharp_edges(options, sharp_edges)
    return options, (seeds, offsets, pinned_faces, sharp)


def anisotropic_options(tolerance: float = _A["tolerance"],
                        feature_angle_degrees: float = _A["feature_angle_degrees"],
                        max_face_valence: int = _A["max_face_valence"], threads: int = _A["threads"],
                        curvature_radius: float = _A["curvature_radius"],
                        sharp_edges: Optional[npt.ArrayLike] = None) -> Tuple[AnisotropicOptions, Any]:
    """An AnisotropicOptions (cagekit_anisotropic_options) from remesh_anisotropic's keyword
    arguments, and the array it points to (keep it alive until the call returns)."""
    options = AnisotropicOptions.new(tolerance=float(tolerance), feature_angle_degrees=float(feature_angle_degrees),
                                     max_face_valence=int(max_face_valence), threads=int(threads),
                                     curvature_radius=float(curvature_radius))
    return options, _lib.set_sharp_edges(options, sharp_edges)


def _report_record(report, name):
    """The report as one flat Record: the quality figures (faces, quads, ...) next to the method's own."""
    record = from_struct(report, name, skip=("struct_size", "quality"))
    return Record(name, **from_struct(report.quality).as_dict(), **record.as_dict())


def remesh_anisotropic(mesh: Mesh, tolerance: float = _A["tolerance"],
                       feature_angle_degrees: float = _A["feature_angle_degrees"],
                       max_face_valence: int = _A["max_face_valence"], threads: int = _A["threads"],
                       curvature_radius: float = _A["curvature_radius"],
                       sharp_edges: Optional[npt.ArrayLike] = None) -> Tuple[Cage, Record]:
    """Remeshes `mesh` (an oriented 2-manifold Mesh; polygons are fan-triangulated first) along its
    curvature lines into a new Cage with crease tags on feature lines. Returns (cage, report); the
    report holds faces, vertices, quads, interior_vertices, valence4_vertices, max_face_valence,
    max_vertex_valence, creases, min_scaled_jacobian, seconds, regions, lines, holes and
    mean_alignment_deg. Options as cagekit_anisotropic_options; `sharp_edges`: the host's sharp
    edges (vertex pairs of `mesh`), feature lines whatever their angle."""
    options, keep_alive = anisotropic_options(tolerance, feature_angle_degrees, max_face_valence, threads,
                                              curvature_radius, sharp_edges)
    report = AnisotropicReport.new()
    out = ctypes.c_void_p()
    mesh._context._call(lib.cagekit_mesh_remesh_anisotropic, mesh._handle, ctypes.byref(options),
                        ctypes.byref(out), ctypes.byref(report), outs=[(out, Cage._release())])
    del keep_alive
    return Cage._wrap(out.value, mesh._context), _report_record(report, "AnisotropicReport")


def remesh_quad(mesh: Mesh, edge_length: float = _Q["edge_length"], regions: int = _Q["regions"],
                region_tolerance: float = _Q["region_tolerance"],
                crease_angle_degrees: float = _Q["crease_angle_degrees"], weights: Sequence[float] = _WEIGHTS,
                refinement_passes: int = _Q["refinement_passes"], threads: int = _Q["threads"],
                seed_faces: Optional[Sequence[int]] = None, pinned_regions: Optional[Sequence[Iterable[int]]] = None,
                sharp_edges: Optional[npt.ArrayLike] = None) -> Tuple[Cage, Record]:
    """Remeshes `mesh` (an oriented 2-manifold Mesh; polygons are fan-triangulated first) by the
    two-step quad-dominant method into a new Cage with crease tags on sharp region boundaries.
    Returns (cage, report); the report holds the quality figures (faces, vertices, quads,
    interior_vertices, valence4_vertices, max_face_valence, max_vertex_valence, creases,
    min_scaled_jacobian, seconds), regions, arcs, requested_regions, split_regions,
    merged_regions, layout_retries, mended_faces, partitioned_regions and reseeded_regions. Options as
    cagekit_quad_remesh_options; weights = (triangle_weight, pentagon_weight, t_joint_weight);
    `seed_faces`: face ids that each start a region; `pinned_regions`: a list of face-id lists,
    each a region the segmentation keeps as it is (counted in `regions`); `sharp_edges`: the
    host's sharp edges (vertex pairs of `mesh`), region borders and creases."""
    options, keep_alive = quad_options(edge_length, regions, region_tolerance, crease_angle_degrees, weights,
                                       refinement_passes, threads, seed_faces, pinned_regions, sharp_edges)
    report = QuadRemeshReport.new()
    out = ctypes.c_void_p()
    mesh._context._call(lib.cagekit_mesh_remesh_quad, mesh._handle, ctypes.byref(options), ctypes.byref(out),
                        ctypes.byref(report), outs=[(out, Cage._release())])
    del keep_alive
    return Cage._wrap(out.value, mesh._context), _report_record(report, "QuadRemeshReport")
