# SPDX-License-Identifier: GPL-3.0-or-later
"""Loading libcagekit and declaring the C API (include/cagekit/cagekit.h) for ctypes.

Every struct is a ctypes.Structure with the header's fields in the header's order, and every
function has its argtypes/restype, in a STRUCTS and a PROTOTYPES dict: those of the core here,
declared once on `lib` below; those of a part of the header that has its own module
(limit_patches.py, scan_to_cage.py) in that module, on its own function objects (Functions), so
that no module changes another's declarations or this module's dicts at import time.
tests/test_abi.py collects the dicts of every module and compares them with the header (the
offsets with a C compiler when one is available). Enumerations are passed as C ints.

The library is looked up, in order, at:
  1. the path in the environment variable CAGEKIT_LIBRARY (the build tree's, in the tests);
  2. a copy next to this package (cagekit/libcagekit.so.2, libcagekit.so, libcagekit.dylib,
     cagekit.dll), as an add-on bundles it;
  3. the system's loader (libcagekit.so.2 on LD_LIBRARY_PATH / the ld.so cache).
Its cagekit_abi_version() must equal ABI_VERSION (the header's CAGEKIT_ABI_VERSION).

The library is loaded with ctypes.CDLL, so every call releases the GIL while it runs (other Python
threads keep running during a long fit or a deform); callbacks take the GIL back while they run.
"""
import ctypes
import os
import sys
from typing import TYPE_CHECKING, Any, Dict
from ctypes import (CFUNCTYPE, POINTER, Structure, c_char_p, c_double, c_float, c_int, c_int32,
                    c_int64, c_size_t, c_uint32, c_uint64, c_void_p)

ABI_VERSION = 2  # CAGEKIT_ABI_VERSION of the header these declarations follow
SHARP = 10.0     # CAGEKIT_SHARP
MAX_SUBDIVISION_LEVELS = 8
ISSUE_KIND_COUNT = 8

c_enum = c_int
c_bool32 = c_uint32  # cagekit_bool32: 0 or 1
c_status = c_int
_u32p = POINTER(c_uint32)
_u64p = POINTER(c_uint64)


class _Versioned(Structure):
    """A struct that begins with struct_size; new() sets it and any defaults.

    _defaults is the one place a struct's default values are written in Python: the header's
    CAGEKIT_*_INIT list (fields left out are 0 / NULL, as in C, where the list's missing entries
    are zero). The functions' keyword defaults are read from defaults() instead of being written
    again, and tests/test_abi.py compares new() with the header's INIT list field by field."""

    _defaults: Dict[str, Any] = {}

    @classmethod
    def new(cls, **values):
        s = cls()
        s.struct_size = ctypes.sizeof(cls)
        for name, value in {**cls._defaults, **values}.items():
            setattr(s, name, value)
        return s

    @classmethod
    def defaults(cls):
        """{field: value} of every field of new() but struct_size (as ctypes reads it back: int,
        float, None for NULL), for the keyword defaults of the functions that fill the struct."""
        s = cls.new()
        return {name: getattr(s, name) for name, *_ in cls._fields_ if name != "struct_size"}


# --- context ---------------------------------------------------------------------------------
LOG_FN = CFUNCTYPE(None, c_void_p, c_enum, c_char_p)
PROGRESS_FN = CFUNCTYPE(c_int, c_void_p, c_char_p, c_double)


class ContextDesc(_Versioned):
    _fields_ = [("struct_size", c_size_t), ("abi_version", c_uint32), ("log", LOG_FN),
                ("log_user_data", c_void_p), ("log_level", c_enum), ("progress", PROGRESS_FN),
                ("progress_user_data", c_void_p), ("memory_budget_bytes", c_uint64)]
    _defaults = {"abi_version": ABI_VERSION, "log_level": 2}


# --- mesh ------------------------------------------------------------------------------------
class MeshDesc(_Versioned):
    _fields_ = [("struct_size", c_size_t), ("vertex_count", c_uint32), ("positions", c_void_p),
                ("position_type", c_enum), ("position_stride", c_size_t), ("face_count", c_uint32),
                ("face_sizes", c_void_p), ("uniform_face_size", c_uint32), ("face_indices", c_void_p)]
    _defaults = {"position_type": 1, "uniform_face_size": 3}


class ValidationReport(_Versioned):
    _fields_ = [("struct_size", c_size_t), ("valid", c_bool32), ("issue_flags", c_uint32),
                ("issue_counts", c_uint64 * ISSUE_KIND_COUNT)]


class RepairOptions(_Versioned):
    _fields_ = [("struct_size", c_size_t), ("steps", c_uint32), ("weld_tolerance", c_double)]
    _defaults = {"steps": 0x1f | (1 << 6)}


class RepairReport(_Versioned):
    _fields_ = [("struct_size", c_size_t)] + [(name, c_uint64) for name in (
        "welded_vertices", "dropped_invalid_faces", "dropped_degenerate_faces", "dropped_duplicate_faces",
        "split_vertices", "flipped_faces", "removed_unreferenced_vertices", "removed_non_finite_vertices",
        "non_orientable_components")]


class MeshInfo(_Versioned):
    _fields_ = [("struct_size", c_size_t)] + [(name, c_uint64) for name in (
        "vertices", "faces", "edges", "triangles", "quads", "other_polygons", "boundary_edges",
        "boundary_loops", "components", "unreferenced_vertices")] + [
        ("genus", c_int64), ("manifold", c_bool32), ("bbox_min", c_double * 3), ("bbox_max", c_double * 3),
        ("bbox_diagonal", c_double), ("creases", c_uint64), ("corners", c_uint64), ("holes", c_uint64),
        ("invalid_faces", c_uint64)]


# --- files -----------------------------------------------------------------------------------
class WriteOptions(_Versioned):
    _fields_ = [("struct_size", c_size_t), ("format", c_enum), ("ply_binary", c_bool32),
                ("draco_position_bits", c_int), ("draco_speed", c_int)]
    _defaults = {"format": 0, "ply_binary": 1, "draco_position_bits": 14, "draco_speed": 5}


class WriteReport(_Versioned):
    _fields_ = [("struct_size", c_size_t), ("bytes", c_uint64), ("max_position_error", c_double)]


# --- subdivision and evaluation --------------------------------------------------------------
class SubdivideOptions(_Versioned):
    _fields_ = [("struct_size", c_size_t), ("levels", c_uint32), ("limit_positions", c_bool32)]
    _defaults = {"levels": 1, "limit_positions": 0}


class SurfaceOptions(_Versioned):
    _fields_ = [("struct_size", c_size_t), ("isolation_level", c_uint32), ("sharp_isolation_level", c_uint32)]
    _defaults = {"isolation_level": 2, "sharp_isolation_level": 10}


class SurfaceLocation(Structure):
    _fields_ = [("face", c_uint32), ("u", c_double), ("v", c_double)]


class SurfacePoint(Structure):
    _fields_ = [(name, c_double * 3) for name in ("position", "du", "dv", "duu", "duv", "dvv")]


# --- simplification --------------------------------------------------------------------------
class SimplifyOptions(_Versioned):
    _fields_ = [("struct_size", c_size_t), ("tie_break_epsilon", c_double), ("sharp_edges", c_void_p),
                ("sharp_edge_count", c_uint32)]
    _defaults = {"tie_break_epsilon": 0.01}


class LevelInfo(_Versioned):
    _fields_ = [("struct_size", c_size_t), ("faces", c_uint64), ("vertices", c_uint64), ("error", c_double)]


class PolygonalLevelInfo(_Versioned):
    _fields_ = [("struct_size", c_size_t), ("level", c_uint32), ("faces", c_uint64), ("vertices", c_uint64),
                ("faces_with_holes", c_uint64), ("invalid_faces", c_uint64), ("l2_error", c_double),
                ("l21_error", c_double)]


class CageOptions(_Versioned):
    _fields_ = [("struct_size", c_size_t), ("crease_angle_degrees", c_double), ("tag_boundary_edges", c_bool32),
                ("exact_partition_limit", c_uint32), ("input_crease_angle_degrees", c_double),
                ("crease_rule", c_int32), ("feature_angle_degrees", c_double), ("sharp_edges", c_void_p),
                ("sharp_edge_count", c_uint32)]
    _defaults = {"crease_angle_degrees": 30.0, "tag_boundary_edges": 1, "exact_partition_limit": 20,
                 "input_crease_angle_degrees": -1.0, "crease_rule": 0, "feature_angle_degrees": 40.0}


# cagekit_crease_rule, by name (the Python API takes the names).
CREASE_RULES = {"sharp-input": 0, "cluster-angle": 1}


def crease_rule_name(value):
    """The name of the cagekit_crease_rule `value` (the inverse of crease_rule_value)."""
    return {v: k for k, v in CREASE_RULES.items()}[value]


def sharp_edge_array(edges):
    """The host's sharp edges (pairs of vertex indices: a list of pairs or an (E, 2) array; None:
    none) as (ctypes uint32 array of 2E indices, E), for an options struct's sharp_edges /
    sharp_edge_count; keep the array alive until the call returns."""
    pairs = [(int(a), int(b)) for a, b in (edges if edges is not None else [])]
    flat = (c_uint32 * (2 * len(pairs)))(*[v for pair in pairs for v in pair])
    return flat, len(pairs)


def set_sharp_edges(options, edges):
    """Sets options.sharp_edges / sharp_edge_count from `edges` (see sharp_edge_array); returns
    the array to keep alive."""
    flat, count = sharp_edge_array(edges)
    options.sharp_edge_count = count
    options.sharp_edges = ctypes.cast(flat, c_void_p) if count else None
    return flat


def crease_rule_value(rule):
    """The cagekit_crease_rule of "sharp-input" (creases where the scan is sharp, the default) or
    "cluster-angle" (the thesis's rule by the clusters' normals); ValueError otherwise."""
    if rule not in CREASE_RULES:
        raise ValueError("crease_rule must be 'sharp-input' or 'cluster-angle', not %r" % (rule,))
    return CREASE_RULES[rule]


class CageReport(_Versioned):
    _fields_ = [("struct_size", c_size_t)] + [(name, c_uint64) for name in (
        "quads", "triangles", "pentagons", "other_polygons", "creases", "non_optimal_faces",
        "non_manifold_edges", "diagonals_flipped", "cells_merged")]


class ApproximationError(_Versioned):
    _fields_ = [("struct_size", c_size_t), ("hausdorff_rel", c_double), ("hausdorff_sym_rel", c_double),
                ("mean_rel", c_double)]


# --- fitting ---------------------------------------------------------------------------------
class FitOptions(_Versioned):
    _fields_ = [("struct_size", c_size_t), ("max_passes", c_uint32), ("tolerance", c_double),
                ("fairing", c_double), ("tangential_weight", c_double), ("keep_crease_vertices", c_bool32),
                ("projection", c_enum), ("solver", c_enum), ("threads", c_uint32),
                ("max_projection_steps", c_uint32), ("projection_epsilon", c_double),
                ("projection_seed_resolution", c_uint32), ("weak_support_fraction", c_double),
                ("weak_fairing", c_double), ("select_best_two_sided", c_bool32),
                ("reverse_sample_factor", c_double), ("crease_feature_reach", c_double)]
    _defaults = {"max_passes": 5, "tolerance": 1e-4, "fairing": 0.0, "tangential_weight": 1.0,
                 "keep_crease_vertices": 0, "projection": 0, "solver": 0, "threads": 0,
                 "max_projection_steps": 500, "projection_epsilon": 1e-6, "projection_seed_resolution": 4,
                 "weak_support_fraction": 0.05, "weak_fairing": 1.0, "select_best_two_sided": 1,
                 "reverse_sample_factor": 0.0, "crease_feature_reach": 0.02}


class FitPass(Structure):
    _fields_ = [("l2", c_double), ("rms_rel", c_double), ("max_rel", c_double), ("mean_rel", c_double),
                ("max_rel_interior", c_double), ("seconds", c_double), ("unconverged_projections", c_uint64),
                ("mean_projection_steps", c_double)]


class FitTwoSided(Structure):
    _fields_ = [("surface_to_scan_max_rel", c_double), ("surface_to_scan_rms_rel", c_double),
                ("two_sided_rms_rel", c_double)]


class FitReport(_Versioned):
    _fields_ = [("struct_size", c_size_t), ("pass_count", c_uint32),
                ("stopped_by_tolerance", c_bool32), ("rejected_last_step", c_bool32),
                ("fairing_used", c_bool32), ("unsupported_control_vertices", c_uint64), ("bbox_diagonal", c_double),
                ("seconds", c_double), ("initial", FitPass), ("final", FitPass), ("best_pass", c_uint32),
                ("weakly_supported_control_vertices", c_uint64), ("initial_two_sided", FitTwoSided),
                ("final_two_sided", FitTwoSided)]


# --- multiresolution -------------------------------------------------------------------------
class BindOptions(_Versioned):
    _fields_ = [("struct_size", c_size_t), ("mode", c_enum), ("exact_normals", c_bool32), ("threads", c_uint32),
                ("sharp_angle_degrees", c_double)]
    _defaults = {"mode": 0, "exact_normals": 0, "threads": 0, "sharp_angle_degrees": -1.0}


class BindingInfo(_Versioned):
    _fields_ = [("struct_size", c_size_t), ("vertex_count", c_uint32), ("control_count", c_uint32),
                ("basis_entries", c_uint64), ("max_sideways_residual", c_double),
                ("vertices_with_sideways_residual", c_uint64), ("bbox_diagonal", c_double),
                ("has_exact_normals", c_bool32), ("deform_bytes_per_vertex", c_double), ("compact_cells", c_uint32),
                ("irregular_vertices", c_uint32), ("scan_vertex_count", c_uint32), ("has_sector_split", c_bool32)]


# --- GL deformer (declared for completeness; it needs the host's GL context) ------------------
GL_PROC = CFUNCTYPE(None)
GL_GET_PROC_ADDRESS_FN = CFUNCTYPE(c_void_p, c_char_p, c_void_p)


class GlDeformerOptions(_Versioned):
    _fields_ = [("struct_size", c_size_t), ("optimize_vertex_cache", c_bool32)]
    _defaults = {"optimize_vertex_cache": 1}


class GlDeformerBuffers(_Versioned):
    _fields_ = [("struct_size", c_size_t)] + [(name, c_uint32) for name in (
        "position_buffer", "position_offset", "position_stride", "normal_buffer", "normal_offset",
        "normal_stride", "component_type", "vertex_count", "index_buffer", "index_count", "index_type")]


class GlDeformerInfo(_Versioned):
    _fields_ = [("struct_size", c_size_t), ("renderer", c_char_p), ("version", c_char_p), ("is_es", c_bool32),
                ("vertex_count", c_uint32), ("control_count", c_uint32), ("index_count", c_uint32),
                ("acmr_before", c_double), ("acmr_after", c_double), ("gpu_bytes", c_uint64),
                ("reference_floats_per_vertex", c_uint32), ("reference_max_edited", c_uint32)]


STRUCTS = {
    "cagekit_context_desc": ContextDesc, "cagekit_mesh_desc": MeshDesc,
    "cagekit_validation_report": ValidationReport, "cagekit_repair_options": RepairOptions,
    "cagekit_repair_report": RepairReport, "cagekit_mesh_info": MeshInfo, "cagekit_write_options": WriteOptions,
    "cagekit_write_report": WriteReport, "cagekit_subdivide_options": SubdivideOptions,
    "cagekit_surface_options": SurfaceOptions, "cagekit_surface_location": SurfaceLocation,
    "cagekit_surface_point": SurfacePoint, "cagekit_simplify_options": SimplifyOptions,
    "cagekit_level_info": LevelInfo, "cagekit_polygonal_level_info": PolygonalLevelInfo,
    "cagekit_cage_options": CageOptions, "cagekit_cage_report": CageReport,
    "cagekit_approximation_error": ApproximationError, "cagekit_fit_options": FitOptions,
    "cagekit_fit_pass": FitPass, "cagekit_fit_report": FitReport, "cagekit_fit_two_sided": FitTwoSided, "cagekit_bind_options": BindOptions,
    "cagekit_binding_info": BindingInfo, "cagekit_gl_deformer_options": GlDeformerOptions,
    "cagekit_gl_deformer_buffers": GlDeformerBuffers, "cagekit_gl_deformer_info": GlDeformerInfo,
}

# --- functions: name -> (restype, argtypes) ---------------------------------------------------
_h = c_void_p  # every handle type is an opaque pointer
_p = c_void_p  # caller buffers (numpy arrays are passed by address)
_pp = POINTER(c_void_p)  # handle outputs
_S = c_status


def _ptr(struct):
    return POINTER(struct)


PROTOTYPES = {
    "cagekit_version": (c_uint32, []),
    "cagekit_version_string": (c_char_p, []),
    "cagekit_abi_version": (c_uint32, []),
    "cagekit_status_string": (c_char_p, [c_status]),
    # context
    "cagekit_context_create": (_S, [_ptr(ContextDesc), _pp]),
    "cagekit_context_retain": (None, [_h]),
    "cagekit_context_release": (None, [_h]),
    "cagekit_context_set_progress": (_S, [_h, PROGRESS_FN, c_void_p]),
    "cagekit_context_cancel": (None, [_h]),
    "cagekit_context_reset_cancel": (None, [_h]),
    "cagekit_last_error_message": (c_char_p, [_h]),
    # blob
    "cagekit_blob_data": (c_void_p, [_h]),
    "cagekit_blob_size": (c_size_t, [_h]),
    "cagekit_blob_retain": (None, [_h]),
    "cagekit_blob_release": (None, [_h]),
    # mesh
    "cagekit_mesh_create": (_S, [_h, _ptr(MeshDesc), _pp]),
    "cagekit_mesh_retain": (None, [_h]),
    "cagekit_mesh_release": (None, [_h]),
    "cagekit_mesh_get_counts": (_S, [_h, _u32p, _u32p, _u64p]),
    "cagekit_mesh_get_positions": (_S, [_h, c_enum, c_uint32, _u32p, _p]),
    "cagekit_mesh_get_faces": (_S, [_h, c_uint32, _u32p, _p, c_uint64, _u64p, _p]),
    "cagekit_mesh_validate": (_S, [_h, _ptr(ValidationReport)]),
    "cagekit_mesh_repair": (_S, [_h, _ptr(RepairOptions), _pp, _ptr(RepairReport)]),
    "cagekit_mesh_get_info": (_S, [_h, _ptr(MeshInfo)]),
    # cage
    "cagekit_cage_create": (_S, [_h, _pp]),
    "cagekit_cage_retain": (None, [_h]),
    "cagekit_cage_release": (None, [_h]),
    "cagekit_cage_get_mesh": (_S, [_h, _pp]),
    "cagekit_cage_set_creases": (_S, [_h, c_uint32, _p, _p]),
    "cagekit_cage_get_creases": (_S, [_h, c_uint32, _u32p, _p, _p]),
    "cagekit_cage_set_corners": (_S, [_h, c_uint32, _p, _p]),
    "cagekit_cage_get_corners": (_S, [_h, c_uint32, _u32p, _p, _p]),
    "cagekit_cage_set_holes": (_S, [_h, c_uint32, _p]),
    "cagekit_cage_get_holes": (_S, [_h, c_uint32, _u32p, _p]),
    "cagekit_cage_set_boundary_rule": (_S, [_h, c_enum]),
    "cagekit_cage_get_boundary_rule": (_S, [_h, POINTER(c_enum)]),
    "cagekit_cage_get_info": (_S, [_h, _ptr(MeshInfo)]),
    # files
    "cagekit_mesh_read_file": (_S, [_h, c_char_p, c_enum, _pp]),
    "cagekit_mesh_read_memory": (_S, [_h, _p, c_size_t, c_enum, _pp]),
    "cagekit_cage_read_file": (_S, [_h, c_char_p, c_enum, _pp]),
    "cagekit_cage_read_memory": (_S, [_h, _p, c_size_t, c_enum, _pp]),
    "cagekit_mesh_write_file": (_S, [_h, c_char_p, _ptr(WriteOptions), _ptr(WriteReport)]),
    "cagekit_mesh_write_memory": (_S, [_h, _ptr(WriteOptions), _pp, _ptr(WriteReport)]),
    "cagekit_cage_write_file": (_S, [_h, c_char_p, _ptr(WriteOptions), _ptr(WriteReport)]),
    "cagekit_cage_write_memory": (_S, [_h, _ptr(WriteOptions), _pp, _ptr(WriteReport)]),
    # subdivision, limit surface
    "cagekit_cage_subdivide": (_S, [_h, _ptr(SubdivideOptions), _pp]),
    "cagekit_cage_get_limit_points": (_S, [_h, c_uint32, _u32p, _p, _p]),
    "cagekit_surface_create": (_S, [_h, _ptr(SurfaceOptions), _pp]),
    "cagekit_surface_retain": (None, [_h]),
    "cagekit_surface_release": (None, [_h]),
    "cagekit_surface_get_counts": (_S, [_h, _u32p, _u32p]),
    "cagekit_surface_get_ptex_face": (_S, [_h, c_uint32, c_uint32, _u32p]),
    "cagekit_surface_evaluate": (_S, [_h, _p, c_uint32, _p, _p]),
    "cagekit_surface_evaluate_basis": (_S, [_h, _ptr(SurfaceLocation), c_uint32, _u32p, _p, _p, _p, _p, _p, _p,
                                            _p]),
    # simplification
    "cagekit_hierarchy_create": (_S, [_h, _ptr(SimplifyOptions), _pp]),
    "cagekit_hierarchy_retain": (None, [_h]),
    "cagekit_hierarchy_release": (None, [_h]),
    "cagekit_hierarchy_get_level_count": (_S, [_h, _u32p]),
    "cagekit_hierarchy_get_level_info": (_S, [_h, c_uint32, _ptr(LevelInfo)]),
    "cagekit_hierarchy_find_level": (_S, [_h, c_enum, c_double, _u32p]),
    "cagekit_hierarchy_set_level": (_S, [_h, c_uint32]),
    "cagekit_hierarchy_get_current_level": (_S, [_h, _u32p]),
    "cagekit_hierarchy_get_current_info": (_S, [_h, _ptr(PolygonalLevelInfo)]),
    "cagekit_hierarchy_get_faces": (_S, [_h, c_uint32, _u32p, _p, c_uint32, _u32p, _p, c_uint64, _u64p, _p]),
    "cagekit_hierarchy_get_clusters": (_S, [_h, c_uint32, _u32p, _p]),
    "cagekit_hierarchy_get_polygon_mesh": (_S, [_h, _pp]),
    "cagekit_hierarchy_get_refined_polygon_mesh": (_S, [_h, c_double, _pp]),
    "cagekit_hierarchy_build_cage": (_S, [_h, _ptr(CageOptions), _pp, _ptr(CageReport)]),
    "cagekit_mesh_measure_error": (_S, [_h, _h, _ptr(ApproximationError)]),
    # fitting
    "cagekit_cage_fit": (_S, [_h, _h, _ptr(FitOptions), _pp, _ptr(FitReport), c_uint32, _u32p, _ptr(FitPass)]),
    # multiresolution
    "cagekit_multires_bind": (_S, [_h, _h, _ptr(BindOptions), _pp]),
    "cagekit_binding_retain": (None, [_h]),
    "cagekit_binding_release": (None, [_h]),
    "cagekit_binding_get_info": (_S, [_h, _ptr(BindingInfo)]),
    "cagekit_binding_write_file": (_S, [_h, c_char_p]),
    "cagekit_binding_write_memory": (_S, [_h, _pp]),
    "cagekit_binding_read_file": (_S, [_h, c_char_p, c_uint32, _pp]),
    "cagekit_binding_read_memory": (_S, [_h, _p, c_size_t, c_uint32, _pp]),
    "cagekit_binding_get_vertex_sources": (_S, [_h, c_uint32, _u32p, _p]),
    "cagekit_binding_get_deformer_vertex_order": (_S, [_h, c_uint32, _u32p, _p]),
    "cagekit_binding_get_faces": (_S, [_h, c_uint32, _u32p, _p, c_uint64, _u64p, _p]),
    "cagekit_binding_get_cage": (_S, [_h, _pp]),
    "cagekit_cpu_deformer_create": (_S, [_h, c_uint32, _pp]),
    "cagekit_cpu_deformer_retain": (None, [_h]),
    "cagekit_cpu_deformer_release": (None, [_h]),
    "cagekit_cpu_deformer_deform": (_S, [_h, _p, c_uint32, c_enum, c_uint32, _u32p, _p, _p]),
    "cagekit_cpu_deformer_update": (_S, [_h, _p, c_uint32, _p, c_uint32, c_enum, c_uint32, _u32p, _p, _p, _u32p]),
    "cagekit_cpu_deformer_deform_f32": (_S, [_h, _p, c_uint32, c_enum, c_uint32, _u32p, _p, _p]),
    "cagekit_cpu_deformer_update_f32": (_S, [_h, _p, c_uint32, _p, c_uint32, c_enum, c_uint32, _u32p, _p, _p, _u32p]),
    # GL deformer
    "cagekit_gl_deformer_create": (_S, [_h, _h, GL_GET_PROC_ADDRESS_FN, c_void_p, _ptr(GlDeformerOptions), _pp]),
    "cagekit_gl_deformer_retain": (None, [_h]),
    "cagekit_gl_deformer_release": (None, [_h]),
    "cagekit_gl_deformer_deform": (_S, [_h, _p, c_uint32, c_enum]),
    "cagekit_gl_deformer_get_buffers": (_S, [_h, _ptr(GlDeformerBuffers)]),
    "cagekit_gl_deformer_get_info": (_S, [_h, _ptr(GlDeformerInfo)]),
    "cagekit_gl_deformer_set_reference_set": (_S, [_h, _p, c_uint32, _p, c_uint32]),
    "cagekit_gl_deformer_deform_reference": (_S, [_h, _p, c_uint32]),
    "cagekit_gl_deformer_set_reference_affine": (_S, [_h, _p, c_uint32, _p, _p, c_uint32]),
    "cagekit_gl_deformer_deform_reference_affine": (_S, [_h, _p]),
    "cagekit_gl_deformer_read_back": (_S, [_h, c_uint32, _u32p, _p, _p]),
}


def _library_names():
    if sys.platform == "win32":
        return ["cagekit.dll", "libcagekit.dll"]
    if sys.platform == "darwin":
        return ["libcagekit.1.dylib", "libcagekit.dylib"]
    return ["libcagekit.so.%d" % ABI_VERSION, "libcagekit.so"]


def _candidates():
    """(description, path or name) in lookup order."""
    found = []
    env = os.environ.get("CAGEKIT_LIBRARY")
    if env:
        found.append(("CAGEKIT_LIBRARY", env))
    here = os.path.dirname(os.path.abspath(__file__))
    for name in _library_names():
        path = os.path.join(here, name)
        if os.path.exists(path):
            found.append(("next to the package", path))
    for name in _library_names():
        found.append(("system loader", name))
    return found


def _load():
    errors = []
    for where, path in _candidates():
        try:
            lib = ctypes.CDLL(path)
        except OSError as e:
            if where == "CAGEKIT_LIBRARY":
                raise ImportError("cagekit: CAGEKIT_LIBRARY=%s cannot be loaded: %s" % (path, e)) from e
            errors.append("%s (%s): %s" % (path, where, e))
            continue
        return lib, path
    raise ImportError("cagekit: libcagekit not found; set CAGEKIT_LIBRARY to the path of libcagekit.so "
                      "(e.g. build/sdk/capi/libcagekit.so) or copy it next to the package. Tried:\n  "
                      + "\n  ".join(errors))


def _missing(name):
    return ImportError("cagekit: the loaded libcagekit has no %s (an older library?)" % name)


def _declare(lib):
    """Declares PROTOTYPES on lib's shared function objects (lib.name), once, below.

    remesh.py still adds its declarations to PROTOTYPES and STRUCTS and calls this again; it is to
    declare its own with Functions as limit_patches.py does (issue 22), then this is called once."""
    for name, (restype, argtypes) in PROTOTYPES.items():
        try:
            fn = getattr(lib, name)
        except AttributeError as e:
            raise _missing(name) from e
        fn.restype = restype
        fn.argtypes = argtypes
    return lib


class Functions:
    """The C functions of one module's PROTOTYPES, as attributes (fns.cagekit_...).

    Each is a function object of its own (lib[name] makes a new one; lib.name is shared and
    cached), so that a module declaring its part of the header changes neither `lib` nor another
    module's functions. ImportError naming the function when the loaded library lacks one."""

    def __init__(self, prototypes):
        for name, (restype, argtypes) in prototypes.items():
            try:
                fn = lib[name]
            except AttributeError as e:
                raise _missing(name) from e
            fn.restype = restype
            fn.argtypes = argtypes
            setattr(self, name, fn)

    if TYPE_CHECKING:  # the functions, set above, for type checkers
        def __getattr__(self, name: str) -> Any: ...


lib, path = _load()
_declare(lib)
abi = lib.cagekit_abi_version()
if abi != ABI_VERSION:
    raise ImportError("cagekit: %s has ABI version %d; this package needs ABI version %d"
                      % (path, abi, ABI_VERSION))


def address(array):
    """The address of a numpy array's data (None for None), for the c_void_p buffer arguments."""
    return None if array is None else array.ctypes.data
