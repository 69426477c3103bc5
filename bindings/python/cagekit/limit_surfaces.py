# SPDX-License-Identifier: GPL-3.0-or-later
"""LimitSurfaces: a cage's limit surface as one B-spline surface per ptex face, for CAD kernels
(cagekit_limit_surfaces_*).

    surfaces = cagekit.LimitSurfaces(cage, tolerance=1e-4, max_level=5)  # or cagekit.limit_surfaces(...)
    surfaces.info.surface_count, surfaces.info.max_error_rel, surfaces.info.max_normal_jump_deg
    s = surfaces[k]            # one BSplineSurface (also: for s in surfaces)
    s.degree_u, s.degree_v     # 3, 3
    s.knots_u, s.knots_v       # (num_u + degree_u + 1,) float64: clamped, end knots repeated degree + 1 times
    s.control_points           # (num_v, num_u, 3) float64: [j, i] has weight N_i(u) N_j(v)
    s.ptex_face, s.cage_face, s.exact, s.error, s.parametric_error, s.max_normal_deviation_deg
    s.sides[0..3]              # kind (BorderKind), max_normal_jump_deg, neighbours
    surfaces.evaluate(k, uv)   # points of surface k at (u, v) (Cox-de Boor)

A surface's (u, v) in [0, 1]^2 is the ptex location (s.ptex_face, u, v) of cagekit.Surface.
Sides: 0 is v = 0 (parameter u), 1 is u = 1 (parameter v), 2 is v = 1 (parameter u), 3 is u = 0
(parameter v). A neighbour (surface, side, t0, t1, n0, n1) covers [t0, t1] of this side; the
neighbour's side parameter is n0 + (t - t0) / (t1 - t0) * (n1 - n0).

Exact surfaces (regular regions) ARE the limit surface; next to extraordinary vertices a surface
approximates it within the tolerance where max_level allows. Measured per surface (model units):
`parametric_error`, the largest distance to the limit surface at equal parameters, and `error`,
the two-sided distance (far samples projected onto the other surface; <= parametric_error).
Shared borders are the same curves, and across smooth borders the normals agree (G1); creases are
C0 borders. Knot vectors differ between surfaces.

Creation is a long operation (progress stage "limit B-spline surfaces", cancel, the context's
memory budget). The object is immutable; each surface is read once, on first use, and cached
(its arrays are handed out as copies).

The C declarations of this part of the header are made here, in this module's STRUCTS and
PROTOTYPES and on its own function objects (`lib`, a _lib.Functions), which change nothing in
_lib; tests/test_abi.py finds them and checks them with the rest.
"""
from __future__ import annotations

import ctypes
import enum
from typing import Any, Dict, Iterator, List, Optional, Sequence, Tuple
from ctypes import POINTER, Structure, c_double, c_size_t, c_uint32, c_void_p

from . import _lib
from ._errors import InvalidArgumentError
from ._handle import Handle
from ._numpy import np, npt
from ._records import Record, from_struct
from .cage import Cage


class BorderKind(enum.IntEnum):
    """cagekit_surface_border_kind: what lies across a side of a surface."""
    BOUNDARY = 0      # a boundary edge (or next to a hole): no neighbour
    SMOOTH = 1        # shared with one neighbour, tangent-continuous (G1)
    CREASE = 2        # shared along an infinitely sharp crease (C0)
    NON_MANIFOLD = 3  # a cage edge in more than two faces (sharp): the border curve is shared by all


_DIRECTION_U, _DIRECTION_V = 0, 1  # cagekit_surface_direction


# --- declarations (include/cagekit/cagekit.h, "limit surface as B-spline surfaces") ----------------
class LimitSurfaceOptions(_lib._Versioned):
    _fields_ = [("struct_size", c_size_t), ("tolerance", c_double), ("max_level", c_uint32),
                ("min_level", c_uint32), ("max_normal_jump_deg", c_double), ("threads", c_uint32)]
    _defaults = {"tolerance": 1e-4, "max_level": 5, "min_level": 1, "max_normal_jump_deg": 0.5, "threads": 0}


class LimitSurfaceInfo(_lib._Versioned):
    _fields_ = [("struct_size", c_size_t), ("surface_count", c_uint32), ("exact_count", c_uint32),
                ("approximated_count", c_uint32), ("over_tolerance_count", c_uint32), ("folded_count", c_uint32),
                ("level", c_uint32), ("ptex_face_count", c_uint32), ("limit_fold_points", c_uint32), ("max_error", c_double),
                ("max_error_rel", c_double), ("max_parametric_error", c_double),
                ("max_normal_deviation_deg", c_double), ("max_normal_jump_deg", c_double),
                ("max_crease_angle_deg", c_double), ("bbox_diagonal", c_double), ("tolerance", c_double)]


class LimitSurfaceSide(Structure):
    _fields_ = [("kind", _lib.c_enum), ("neighbour_count", c_uint32), ("max_normal_jump_deg", c_double)]


class LimitSurface(Structure):
    _fields_ = [("ptex_face", c_uint32), ("cage_face", c_uint32), ("degree_u", c_uint32), ("degree_v", c_uint32),
                ("knot_count_u", c_uint32), ("knot_count_v", c_uint32), ("num_u", c_uint32), ("num_v", c_uint32),
                ("exact", _lib.c_bool32), ("reserved", c_uint32), ("error", c_double),
                ("parametric_error", c_double), ("max_normal_deviation_deg", c_double),
                ("sides", LimitSurfaceSide * 4)]


class LimitSurfaceNeighbour(Structure):
    _fields_ = [("surface", c_uint32), ("side", c_uint32), ("t0", c_double), ("t1", c_double), ("n0", c_double),
                ("n1", c_double)]


STRUCTS = {"cagekit_limit_surface_options": LimitSurfaceOptions, "cagekit_limit_surface_info": LimitSurfaceInfo,
           "cagekit_limit_surface_side": LimitSurfaceSide, "cagekit_limit_surface": LimitSurface,
           "cagekit_limit_surface_neighbour": LimitSurfaceNeighbour}
_u32p = POINTER(c_uint32)
PROTOTYPES = {
    "cagekit_limit_surfaces_create": (_lib.c_status, [c_void_p, POINTER(LimitSurfaceOptions), POINTER(c_void_p)]),
    "cagekit_limit_surfaces_retain": (None, [c_void_p]),
    "cagekit_limit_surfaces_release": (None, [c_void_p]),
    "cagekit_limit_surfaces_get_info": (_lib.c_status, [c_void_p, POINTER(LimitSurfaceInfo)]),
    "cagekit_limit_surfaces_get_surface": (_lib.c_status, [c_void_p, c_uint32, POINTER(LimitSurface)]),
    "cagekit_limit_surfaces_get_knots": (_lib.c_status, [c_void_p, c_uint32, _lib.c_enum, c_uint32, _u32p, c_void_p]),
    "cagekit_limit_surfaces_get_control_points": (_lib.c_status, [c_void_p, c_uint32, c_uint32, _u32p, c_void_p]),
    "cagekit_limit_surfaces_get_neighbours": (_lib.c_status, [c_void_p, c_uint32, c_uint32, c_uint32, _u32p,
                                                              c_void_p]),
}
lib = _lib.Functions(PROTOTYPES)  # ImportError naming the function when the loaded library lacks one


_D = LimitSurfaceOptions.defaults()  # CAGEKIT_LIMIT_SURFACE_OPTIONS_INIT, written once (in LimitSurfaceOptions)


def bspline_basis(knots: npt.ArrayLike, degree: int, x: npt.ArrayLike) -> np.ndarray:
    """(n, num) values of the B-spline basis functions N_0..N_{num-1} of the clamped knot vector
    `knots` (num = len(knots) - degree - 1) at x (n,), by the Cox-de Boor recursion (0/0 = 0;
    x = the last knot belongs to the last nonempty span)."""
    knots = np.asarray(knots, dtype=np.float64)
    x = np.asarray(x, dtype=np.float64).reshape(-1, 1)
    spans = np.nonzero(knots[:-1] < knots[1:])[0]
    last = spans[-1] if len(spans) else len(knots) - 2
    lo, hi = knots[:-1], knots[1:]
    n = ((lo <= x) & (x < hi)).astype(np.float64)
    n[:, last] = np.where(x[:, 0] == hi[last], 1.0, n[:, last])
    for p in range(1, degree + 1):
        m = len(knots) - p - 1
        left_den = knots[p:p + m] - knots[:m]
        right_den = knots[p + 1:p + 1 + m] - knots[1:1 + m]
        with np.errstate(divide="ignore", invalid="ignore"):
            a = np.where(left_den > 0, (x - knots[:m]) / np.where(left_den > 0, left_den, 1.0), 0.0)
            b = np.where(right_den > 0, (knots[p + 1:p + 1 + m] - x) / np.where(right_den > 0, right_den, 1.0), 0.0)
        n = a * n[:, :m] + b * n[:, 1:m + 1]
    return n


class BSplineSurface:
    """One surface (see the module doc): ptex_face, cage_face, degree_u, degree_v, knots_u,
    knots_v, num_u, num_v, control_points (num_v, num_u, 3), exact, error (two-sided),
    parametric_error (at equal parameters), max_normal_deviation_deg, sides (4 Records:
    kind, max_normal_jump_deg, neighbours (Records surface, side, t0, t1, n0, n1))."""

    def __init__(self, desc: Any, knots_u: np.ndarray, knots_v: np.ndarray, points: np.ndarray,
                 neighbours: Sequence[Sequence[Any]]) -> None:
        self.ptex_face, self.cage_face = int(desc.ptex_face), int(desc.cage_face)
        self.degree_u, self.degree_v = int(desc.degree_u), int(desc.degree_v)
        self.num_u, self.num_v = int(desc.num_u), int(desc.num_v)
        self.exact, self.error = bool(desc.exact), float(desc.error)
        self.parametric_error = float(desc.parametric_error)
        self.max_normal_deviation_deg = float(desc.max_normal_deviation_deg)
        self._knots_u, self._knots_v, self._points = knots_u, knots_v, points
        self.sides = tuple(Record("SurfaceSide", kind=BorderKind(desc.sides[k].kind),
                                  max_normal_jump_deg=float(desc.sides[k].max_normal_jump_deg),
                                  neighbours=[from_struct(n, "SurfaceNeighbour") for n in neighbours[k]])
                           for k in range(4))

    @property
    def knots_u(self) -> np.ndarray:
        return self._knots_u.copy()

    @property
    def knots_v(self) -> np.ndarray:
        return self._knots_v.copy()

    @property
    def control_points(self) -> np.ndarray:
        """(num_v, num_u, 3) float64: [j, i] is control point (i, j), of weight N_i(u) N_j(v)."""
        return self._points.copy()

    def evaluate(self, uv: npt.ArrayLike) -> np.ndarray:
        """(n, 3) points at (u, v) pairs uv (n, 2) in [0, 1]^2."""
        uv = np.asarray(uv, dtype=np.float64).reshape(-1, 2)
        bu = bspline_basis(self._knots_u, self.degree_u, uv[:, 0])  # (n, num_u)
        bv = bspline_basis(self._knots_v, self.degree_v, uv[:, 1])  # (n, num_v)
        return np.einsum("ni,nj,jic->nc", bu, bv, self._points)

    def __repr__(self) -> str:
        return "BSplineSurface(ptex_face=%d, cage_face=%d, %dx%d control points, exact=%s, error=%.3g)" % (
            self.ptex_face, self.cage_face, self.num_u, self.num_v, self.exact, self.error)


class LimitSurfaces(Handle):
    """The limit surface of a cage as B-spline surfaces, one per ptex face (see the module doc)."""

    _release_name = "cagekit_limit_surfaces_release"
    _functions = lib
    _kind = "limit surfaces"

    def __init__(self, cage: Cage, tolerance: float = _D["tolerance"], max_level: int = _D["max_level"],
                 min_level: int = _D["min_level"], max_normal_jump_deg: float = _D["max_normal_jump_deg"],
                 threads: int = _D["threads"]) -> None:
        """tolerance: the largest distance allowed between an approximated surface and the limit
        surface, as a fraction of the bounding-box diagonal of the cage's control points (> 0);
        max_level: the largest knot level tried (1..7; up to 2^level spans per quad side);
        min_level: the smallest (1..max_level); max_normal_jump_deg: a surface whose normal jumps
        by more across a smooth border gets more knots (> 0); threads: worker threads for the
        fits (0: the hardware's; the surfaces do not depend on it). Bad values raise
        InvalidArgumentError with the SDK's message. Long operation (progress stage "limit
        B-spline surfaces", cancel)."""
        options = LimitSurfaceOptions.new(tolerance=float(tolerance), max_level=int(max_level),
                                          min_level=int(min_level), max_normal_jump_deg=float(max_normal_jump_deg),
                                          threads=int(threads))
        out = ctypes.c_void_p()
        cage._context._call(lib.cagekit_limit_surfaces_create, cage._handle, ctypes.byref(options),
                            ctypes.byref(out), outs=[(out, self._release())])
        Handle.__init__(self, out.value, cage._context)
        self._info: Optional[Record] = None
        self._surfaces: Dict[int, BSplineSurface] = {}

    @property
    def info(self) -> Record:
        """Record: surface_count, exact_count, approximated_count, over_tolerance_count (also
        folded ones), folded_count, level (the largest knot level used), ptex_face_count,
        limit_fold_points (border samples where the limit itself folds: left out of the jump), max_error
        (two-sided, model units), max_error_rel (of bbox_diagonal), max_parametric_error,
        max_normal_deviation_deg, max_normal_jump_deg (smooth borders), max_crease_angle_deg
        (crease / non-manifold borders), bbox_diagonal, tolerance (absolute)."""
        if self._info is None:
            info = LimitSurfaceInfo.new()
            self._context._call(lib.cagekit_limit_surfaces_get_info, self._handle, ctypes.byref(info))
            self._info = from_struct(info, "LimitSurfaceInfo")
        return self._info

    def __len__(self) -> int:
        return self.info.surface_count

    def __iter__(self) -> Iterator[BSplineSurface]:
        return (self[k] for k in range(len(self)))

    def __getitem__(self, index: int) -> BSplineSurface:
        """Surface `index` (0 .. len - 1, ordered by ptex face; negative indices count from the end)."""
        n = len(self)
        k = int(index)
        if k < 0:
            k += n
        if not 0 <= k < n:
            raise InvalidArgumentError("surface index %d is out of range (%d surfaces)" % (int(index), n))
        if k not in self._surfaces:
            self._surfaces[k] = self._read(k)
        return self._surfaces[k]

    def _read(self, k: int) -> BSplineSurface:
        call, h = self._context._call, self._handle
        desc = LimitSurface()
        call(lib.cagekit_limit_surfaces_get_surface, h, k, ctypes.byref(desc))
        count = ctypes.c_uint32()
        knots = []
        for direction, n in ((_DIRECTION_U, desc.knot_count_u), (_DIRECTION_V, desc.knot_count_v)):
            out = np.zeros(n, dtype=np.float64)
            call(lib.cagekit_limit_surfaces_get_knots, h, k, direction, n, ctypes.byref(count), _lib.address(out))
            knots.append(out)
        points = np.zeros((desc.num_v, desc.num_u, 3), dtype=np.float64)
        call(lib.cagekit_limit_surfaces_get_control_points, h, k, desc.num_u * desc.num_v, ctypes.byref(count),
             _lib.address(points))
        neighbours = []
        for side in range(4):
            m = desc.sides[side].neighbour_count
            array = (LimitSurfaceNeighbour * max(m, 1))()
            call(lib.cagekit_limit_surfaces_get_neighbours, h, k, side, m, ctypes.byref(count), array)
            neighbours.append(list(array)[:m])
        return BSplineSurface(desc, knots[0], knots[1], points, neighbours)

    def evaluate(self, index: int, uv: npt.ArrayLike) -> np.ndarray:
        """(n, 3) points of surface `index` at (u, v) pairs uv (n, 2) in [0, 1]^2."""
        return self[index].evaluate(uv)


def limit_surfaces(cage: Cage, tolerance: float = _D["tolerance"], max_level: int = _D["max_level"],
                   min_level: int = _D["min_level"], max_normal_jump_deg: float = _D["max_normal_jump_deg"],
                   threads: int = _D["threads"]) -> LimitSurfaces:
    """LimitSurfaces(cage, tolerance, max_level, min_level, max_normal_jump_deg, threads)."""
    return LimitSurfaces(cage, tolerance=tolerance, max_level=max_level, min_level=min_level,
                         max_normal_jump_deg=max_normal_jump_deg, threads=threads)
