# SPDX-License-Identifier: GPL-3.0-or-later
"""Fitting a cage's limit surface to a scan (thesis ch. 7).

    fitted, report = cagekit.fit(cage, scan, max_passes=5)
    [p.l2 for p in report.passes]     # entry 0: the initial cage; never increasing

Long operation (progress stage "fit", at least once per pass; cancel), using `threads` worker
threads inside the C library; the GIL is released for the whole call.
"""
from __future__ import annotations

import ctypes
import enum
from typing import TYPE_CHECKING, Tuple, TypeVar, Union

from . import _lib, _typing
from ._records import Record, enum_value as _enum, from_struct
from .mesh import Mesh

if TYPE_CHECKING:
    from . import cage as _cage_module
else:
    _cage_module = _typing.loaded("cagekit.cage")  # cage.py imports this module (Cage.fit)


class ProjectionMode(enum.IntEnum):
    EXACT = 0             # closest points on the exact limit surface (default)
    PIECEWISE_LINEAR = 1  # on the level-2 limit mesh: faster, less accurate


class LsqSolver(enum.IntEnum):
    DIRECT = 0  # sparse Cholesky (default)
    CGLS = 1    # conjugate gradients, warm-started


_C = TypeVar("_C", bound="_cage_module.Cage")  # fit() returns a cage of its input's class

_D = _lib.FitOptions.defaults()  # CAGEKIT_FIT_OPTIONS_INIT, written once (in _lib.FitOptions)


def fit(cage: _C, scan: Mesh, max_passes: int = _D["max_passes"], tolerance: float = _D["tolerance"],
        fairing: float = _D["fairing"], tangential_weight: float = _D["tangential_weight"],
        keep_crease_vertices: bool = bool(_D["keep_crease_vertices"]),
        projection: Union[ProjectionMode, int, str] = ProjectionMode(_D["projection"]),
        solver: Union[LsqSolver, int, str] = LsqSolver(_D["solver"]), threads: int = _D["threads"],
        max_projection_steps: int = _D["max_projection_steps"], projection_epsilon: float = _D["projection_epsilon"],
        projection_seed_resolution: int = _D["projection_seed_resolution"],
        crease_feature_reach: float = _D["crease_feature_reach"]) -> Tuple[_C, Record]:
    """Fits `cage` (not changed) to the vertices of `scan` (a Mesh). Returns (new Cage (of the class
    of `cage`) with the same faces and tags, report). The report holds pass_count, passes (a list of records with
    l2, rms_rel, max_rel, mean_rel, max_rel_interior, seconds, unconverged_projections,
    mean_projection_steps; entry 0 = the initial cage), initial, final, stopped_by_tolerance,
    rejected_last_step, fairing_used, unsupported_control_vertices, bbox_diagonal, seconds.
    Option values as the C API's cagekit_fit_options (projection/solver also as names);
    `crease_feature_reach` holds the limit's crease curves on the scan's sharp edges (0: off)."""
    options = _lib.FitOptions.new(
        max_passes=int(max_passes), tolerance=float(tolerance), fairing=float(fairing),
        tangential_weight=float(tangential_weight), keep_crease_vertices=1 if keep_crease_vertices else 0,
        projection=int(_enum(ProjectionMode, projection)), solver=int(_enum(LsqSolver, solver)),
        threads=int(threads), max_projection_steps=int(max_projection_steps),
        projection_epsilon=float(projection_epsilon), projection_seed_resolution=int(projection_seed_resolution),
        crease_feature_reach=float(crease_feature_reach))
    # max_passes + 1 entries always suffice (the fit is not repeated for a second call); a value
    # out of range fails in the library, with its message, before the array is looked at.
    capacity = max(0, min(int(max_passes), 100000)) + 1
    passes = (_lib.FitPass * capacity)()
    pass_count = ctypes.c_uint32()
    report = _lib.FitReport.new()
    out = ctypes.c_void_p()
    cage._context._call(_lib.lib.cagekit_cage_fit, cage._handle, scan._handle, ctypes.byref(options),
                        ctypes.byref(out), ctypes.byref(report), capacity, ctypes.byref(pass_count), passes,
                        outs=[(out, cage._release())])
    # Made through the input's class: this module does not import cage.py, which imports it for
    # Cage.fit, so the two have one import direction.
    fitted = type(cage)._wrap(out.value, cage._context)
    record = from_struct(report, "FitReport", skip=("struct_size",))
    record.passes = [from_struct(passes[i], "FitPass") for i in range(pass_count.value)]
    for name in ("stopped_by_tolerance", "rejected_last_step", "fairing_used"):
        setattr(record, name, bool(getattr(record, name)))
    return fitted, record
