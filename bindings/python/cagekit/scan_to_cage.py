# SPDX-License-Identifier: GPL-3.0-or-later
"""The whole journey from a scan to a fitted cage in one call (cagekit_scan_to_cage).

    cage, limit, report = cagekit.scan_to_cage(scan, method="quad")
    report.used_method, report.fallback_reason, report.limit_to_scan_max_rel, report.self_intersections

Phases: conditioning (repair: weld, drop degenerate/duplicate faces, split non-manifold parts,
orient; optionally keep only the largest component) -> the method (simplify, quad or anisotropic;
an input with fewer faces than the method would make is its own cage) -> a valid cage without new
holes -> the fit (two-sided best state) -> the limit surface measured both ways against the scan
-> the good-result rule. A result that is not good raises QualityError naming the figure (after
falling back from quad / anisotropic to simplify, unless fallback_to_simplify is False). Long
operation (progress, cancel); the GIL is released for the whole call.

The C declarations of this part of the header are made here, in this module's STRUCTS and
PROTOTYPES and on its own function objects (`lib`, a _lib.Functions), which change nothing in
_lib; tests/test_abi.py finds them and checks them with the rest.
"""
from __future__ import annotations

import ctypes
import enum
from ctypes import POINTER, c_char, c_double, c_size_t, c_uint32, c_uint64, c_void_p
from typing import Any, Mapping, Optional, Tuple, Union

from . import _lib
from ._numpy import npt
from ._records import Record, enum_value as _enum, from_struct
from .cage import Cage
from .mesh import Mesh
from .fit import LsqSolver, ProjectionMode
from .remesh import anisotropic_options, quad_options


class ScanMethod(enum.IntEnum):
    SIMPLIFY = 0     # structure-preserving simplification (thesis ch. 3)
    QUAD = 1         # two-step quad-dominant remeshing (thesis ch. 6)
    ANISOTROPIC = 2  # curvature-line remeshing (thesis ch. 5)


class ComponentMode(enum.IntEnum):
    ALL = 0
    LARGEST = 1


# --- declarations (include/cagekit/cagekit.h, "scan to cage") -----------------------------------
class ScanToCageOptions(_lib._Versioned):
    _fields_ = [("struct_size", c_size_t), ("method", _lib.c_enum), ("repair", _lib.c_bool32), ("components", _lib.c_enum),
                ("weld_tolerance_rel", c_double), ("target_query", _lib.c_enum), ("target", c_double),
                ("cage", c_void_p), ("quad", c_void_p), ("anisotropic", c_void_p), ("fit", c_void_p), ("limit_levels", c_uint32),
                ("self_intersection_level", c_uint32), ("max_limit_to_scan_rel", c_double),
                ("limit_to_scan_factor", c_double), ("small_input_faces", c_uint64),
                ("fallback_to_simplify", _lib.c_bool32), ("finer_simplify_attempts", c_uint32),
                ("two_sided_refit_factor", c_double), ("sharp_edges", c_void_p),
                ("sharp_edge_count", c_uint32)]
    _defaults = {"method": 0, "repair": 1, "components": 0, "weld_tolerance_rel": 1e-7, "target_query": 0,
                 "target": 60.0, "cage": None, "quad": None, "anisotropic": None, "fit": None, "limit_levels": 3,
                 "self_intersection_level": 2, "max_limit_to_scan_rel": 0.05, "limit_to_scan_factor": 3.0,
                 "small_input_faces": 1000, "fallback_to_simplify": 1, "finer_simplify_attempts": 2,
                 "two_sided_refit_factor": 3.0, "sharp_edges": None,
                 "sharp_edge_count": 0}


def _u64(*names):
    return [(n, c_uint64) for n in names]


class ScanToCageReport(_lib._Versioned):
    _fields_ = ([("struct_size", c_size_t)] +
                _u64("input_vertices", "input_faces", "conditioned_vertices", "conditioned_faces", "welded_vertices",
                     "dropped_degenerate_faces", "dropped_duplicate_faces", "split_vertices", "flipped_faces",
                     "non_orientable_components", "removed_unreferenced_vertices", "components",
                     "dropped_components", "dropped_component_faces") +
                [("requested_method", _lib.c_enum), ("used_method", _lib.c_enum), ("fallback", _lib.c_bool32),
                 ("input_is_cage", _lib.c_bool32), ("fallback_reason", c_char * 256), ("level", c_uint32),
                 ("level_count", c_uint32)] +
                _u64("level_faces", "level_faces_with_holes", "cage_vertices", "cage_faces", "cage_quads",
                     "cage_triangles", "creases", "remesh_regions", "remesh_lines", "remesh_holes",
                     "interior_vertices", "valence4_vertices") +
                [("max_face_valence", c_uint32), ("max_vertex_valence", c_uint32), ("mean_alignment_deg", c_double),
                 ("method_scan_to_cage_max_rel", c_double), ("method_cage_to_scan_max_rel", c_double),
                 ("method_mean_rel", c_double)] +
                _u64("input_boundary_loops", "cage_boundary_loops", "holes_added") +
                [("fit_pass_count", c_uint32), ("fit_best_pass", c_uint32), ("fit_initial", _lib.FitPass),
                 ("fit_final", _lib.FitPass), ("fit_initial_two_sided", _lib.FitTwoSided),
                 ("fit_final_two_sided", _lib.FitTwoSided)] +
                _u64("unsupported_control_vertices", "weakly_supported_control_vertices") +
                [("limit_levels", c_uint32), ("limit_faces", c_uint64), ("scan_to_limit_max_rel", c_double),
                 ("limit_to_scan_max_rel", c_double), ("limit_mean_rel", c_double)] +
                _u64("self_intersections", "self_intersection_triangles") +
                [("method_seconds", c_double), ("fit_seconds", c_double), ("seconds", c_double),
                 ("simplify_target_used", c_double)] +
                _u64("scan_self_intersections", "unfitted_self_intersections") +
                [("scan_self_intersections_counted", _lib.c_bool32), ("own_cage_crease_angle_deg", c_double),
                 ("fit_fairing_used", c_double), ("two_sided_refit", _lib.c_bool32),
                 ("one_sided_fit_max_rel", c_double), ("sharp_edges", c_uint64), ("sharp_edges_dropped", c_uint64),
                 ("remesh_reseeded_regions", c_uint64)])


STRUCTS = {"cagekit_scan_to_cage_options": ScanToCageOptions, "cagekit_scan_to_cage_report": ScanToCageReport}
PROTOTYPES = {
    "cagekit_scan_to_cage": (_lib.c_status, [c_void_p, POINTER(ScanToCageOptions), POINTER(c_void_p),
                                             POINTER(c_void_p), POINTER(ScanToCageReport),
                                             POINTER(_lib.FitReport), c_uint32, POINTER(c_uint32),
                                             POINTER(_lib.FitPass)]),
}
lib = _lib.Functions(PROTOTYPES)  # ImportError naming the function when the loaded library lacks one


# CAGEKIT_SCAN_TO_CAGE_OPTIONS_INIT and CAGEKIT_CAGE_OPTIONS_INIT, written once (in the structs).
_D = ScanToCageOptions.defaults()
_CAGE = _lib.CageOptions.defaults()


def scan_to_cage(scan: Mesh, method: Union[ScanMethod, int, str] = ScanMethod(_D["method"]),
                 faces: float = _D["target"], repair: bool = bool(_D["repair"]),
                 components: Union[ComponentMode, int, str] = ComponentMode(_D["components"]),
                 weld_tolerance_rel: float = _D["weld_tolerance_rel"],
                 crease_rule: str = _lib.crease_rule_name(_CAGE["crease_rule"]),
                 feature_angle_degrees: float = _CAGE["feature_angle_degrees"],
                 crease_angle_degrees: float = _CAGE["crease_angle_degrees"],
                 input_crease_angle_degrees: float = _CAGE["input_crease_angle_degrees"],
                 quad: Optional[Mapping[str, Any]] = None, anisotropic: Optional[Mapping[str, Any]] = None,
                 fit: Optional[Mapping[str, Any]] = None, limit_levels: int = _D["limit_levels"],
                 self_intersection_level: int = _D["self_intersection_level"],
                 max_limit_to_scan_rel: float = _D["max_limit_to_scan_rel"],
                 limit_to_scan_factor: float = _D["limit_to_scan_factor"],
                 small_input_faces: int = _D["small_input_faces"],
                 fallback_to_simplify: bool = bool(_D["fallback_to_simplify"]),
                 finer_simplify_attempts: int = _D["finer_simplify_attempts"],
                 two_sided_refit_factor: float = _D["two_sided_refit_factor"],
                 sharp_edges: Optional[npt.ArrayLike] = None) -> Tuple[Cage, Cage, Record]:
    """Runs the journey on `scan` (a Mesh, not changed). Returns (cage, limit, report): the fitted
    Cage with crease tags, its limit mesh (refined `limit_levels` times) as a Cage, and a record
    of every figure of cagekit_scan_to_cage_report (fallback_reason as str, methods as
    ScanMethod). `faces`: simplify's target and the fallback's. Creases as Hierarchy.build_cage
    (crease_rule, feature_angle_degrees, crease_angle_degrees, input_crease_angle_degrees). `quad` / `anisotropic`:
    dicts of cagekit.remesh_quad()'s / remesh_anisotropic()'s keyword arguments; `fit`: a dict
    of cagekit.fit()'s option names. `two_sided_refit_factor`: the last phase's two-sided refit (0: not
    tried; report.two_sided_refit says whether it was kept). `sharp_edges`: the host's sharp edges
    (vertex pairs of `scan`), found again after the conditioning and given to every method
    (report.sharp_edges / sharp_edges_dropped). Raises QualityError when no good result could be
    made."""
    quad_struct, keep_alive = quad_options(**(quad or {}))
    anisotropic_struct, anisotropic_keep_alive = anisotropic_options(**(anisotropic or {}))
    fit_options = None
    if fit is not None:
        f = dict(fit)
        if "projection" in f:
            f["projection"] = int(_enum(ProjectionMode, f["projection"]))
        if "solver" in f:
            f["solver"] = int(_enum(LsqSolver, f["solver"]))
        if "keep_crease_vertices" in f:
            f["keep_crease_vertices"] = 1 if f["keep_crease_vertices"] else 0
        fit_options = _lib.FitOptions.new(**f)
    cage_options = _lib.CageOptions.new(crease_rule=_lib.crease_rule_value(crease_rule),
                                        feature_angle_degrees=float(feature_angle_degrees),
                                        crease_angle_degrees=float(crease_angle_degrees),
                                        input_crease_angle_degrees=float(input_crease_angle_degrees))
    options = ScanToCageOptions.new(
        method=int(_enum(ScanMethod, method)), repair=1 if repair else 0,
        components=int(_enum(ComponentMode, components)), weld_tolerance_rel=float(weld_tolerance_rel),
        target=float(faces), limit_levels=int(limit_levels), self_intersection_level=int(self_intersection_level),
        max_limit_to_scan_rel=float(max_limit_to_scan_rel), limit_to_scan_factor=float(limit_to_scan_factor),
        small_input_faces=int(small_input_faces), fallback_to_simplify=1 if fallback_to_simplify else 0,
        finer_simplify_attempts=int(finer_simplify_attempts),
        two_sided_refit_factor=float(two_sided_refit_factor))
    sharp_keep_alive = _lib.set_sharp_edges(options, sharp_edges)
    options.cage = ctypes.cast(ctypes.pointer(cage_options), c_void_p)
    options.quad = ctypes.cast(ctypes.pointer(quad_struct), c_void_p)
    options.anisotropic = ctypes.cast(ctypes.pointer(anisotropic_struct), c_void_p)
    if fit_options is not None:
        options.fit = ctypes.cast(ctypes.pointer(fit_options), c_void_p)
    report = ScanToCageReport.new()
    cage_out, limit_out = ctypes.c_void_p(), ctypes.c_void_p()
    fit_pass_count = ctypes.c_uint32()  # the fit's states: not returned (the report has the fit's figures)
    scan._context._call(lib.cagekit_scan_to_cage, scan._handle, ctypes.byref(options), ctypes.byref(cage_out),
                        ctypes.byref(limit_out), ctypes.byref(report), None, 0, ctypes.byref(fit_pass_count), None,
                        outs=[(cage_out, Cage._release()), (limit_out, Cage._release())])
    del keep_alive, anisotropic_keep_alive, sharp_keep_alive
    cage = Cage._wrap(cage_out.value, scan._context)
    limit = Cage._wrap(limit_out.value, scan._context)
    record = from_struct(report, "ScanToCageReport", skip=("struct_size", "fallback_reason"))
    record.fallback_reason = report.fallback_reason.decode("utf-8", "replace")
    record.requested_method = ScanMethod(report.requested_method)
    record.used_method = ScanMethod(report.used_method)
    for name in ("fallback", "input_is_cage", "two_sided_refit"):
        setattr(record, name, bool(getattr(record, name)))
    return cage, limit, record
