# SPDX-License-Identifier: GPL-3.0-or-later
"""LimitPatches: a cage's limit surface as bicubic Bezier patches, for export to CAD
(cagekit_limit_patches_*).

    patches = cagekit.LimitPatches(cage, tolerance=1e-4, max_depth=8)   # or cagekit.limit_patches(...)
    patches.info.patch_count, patches.info.max_error_rel
    patches.control_points   # (N, 4, 4, 3) float64: [k, i, j] is the point of weight B_i(s) B_j(t)
    patches.domains          # (N, 4): u0, v0, u1, v1 of each patch in its ptex face
    patches.ptex_faces, patches.cage_faces, patches.exact, patches.errors
    patches.evaluate(k, st)  # Bezier points of patches k at (s, t)

Where the limit surface is one polynomial (regular regions) a patch is exact: it IS the limit
surface there. Elsewhere a region is split as a quadtree (up to max_depth) and each piece
approximated; `errors` holds each approximated patch's measured distance to the limit surface
(model units; for exact ones, rounding level). Patches are ordered by ptex face, then in
quadtree order. Bezier (s, t) in [0, 1]^2 of patch k is the ptex location
(ptex_faces[k], u0 + s (u1 - u0), v0 + t (v1 - v0)) of cagekit.Surface.

Creation is a long operation (progress, cancel) with the cage's context. The object is
immutable; its arrays are read once, on first use, and cached (copies are handed out).

The C declarations of this part of the header are made here, in this module's STRUCTS and
PROTOTYPES and on its own function objects (`lib`, a _lib.Functions), which change nothing in
_lib; tests/test_abi.py finds them and checks them with the rest.
"""
from __future__ import annotations

import ctypes
from typing import Optional, Tuple
from ctypes import POINTER, Structure, c_double, c_size_t, c_uint32, c_void_p

from . import _lib
from ._errors import InvalidArgumentError
from ._handle import Handle
from ._numpy import np, npt
from ._records import Record, from_struct
from .cage import Cage


# --- declarations (include/cagekit/cagekit.h, "limit patches") ----------------------------------
class LimitPatchOptions(_lib._Versioned):
    _fields_ = [("struct_size", c_size_t), ("tolerance", c_double), ("max_depth", c_uint32), ("threads", c_uint32)]
    _defaults = {"tolerance": 1e-4, "max_depth": 8, "threads": 0}


class LimitPatchInfo(_lib._Versioned):
    _fields_ = [("struct_size", c_size_t), ("patch_count", c_uint32), ("exact_count", c_uint32),
                ("approximated_count", c_uint32), ("over_tolerance_count", c_uint32), ("max_error", c_double),
                ("max_error_rel", c_double), ("bbox_diagonal", c_double), ("tolerance", c_double)]


class LimitPatch(Structure):
    _fields_ = [("ptex_face", c_uint32), ("cage_face", c_uint32), ("u0", c_double), ("v0", c_double),
                ("u1", c_double), ("v1", c_double), ("exact", _lib.c_bool32), ("reserved", c_uint32),
                ("error", c_double), ("control_points", c_double * 48)]


STRUCTS = {"cagekit_limit_patch_options": LimitPatchOptions, "cagekit_limit_patch_info": LimitPatchInfo,
           "cagekit_limit_patch": LimitPatch}
PROTOTYPES = {
    "cagekit_limit_patches_create": (_lib.c_status, [c_void_p, POINTER(LimitPatchOptions), POINTER(c_void_p)]),
    "cagekit_limit_patches_retain": (None, [c_void_p]),
    "cagekit_limit_patches_release": (None, [c_void_p]),
    "cagekit_limit_patches_get_info": (_lib.c_status, [c_void_p, POINTER(LimitPatchInfo)]),
    "cagekit_limit_patches_get": (_lib.c_status, [c_void_p, c_uint32, POINTER(c_uint32), c_void_p]),
}
lib = _lib.Functions(PROTOTYPES)  # ImportError naming the function when the loaded library lacks one


_D = LimitPatchOptions.defaults()  # CAGEKIT_LIMIT_PATCH_OPTIONS_INIT, written once (in LimitPatchOptions)


def _patch_dtype():
    """The numpy record type laid out exactly as cagekit_limit_patch (offsets from ctypes)."""
    names, formats, offsets = [], [], []
    for name, ctype in LimitPatch._fields_:
        names.append(name)
        formats.append((np.float64, (48,)) if name == "control_points" else
                       (np.float64 if ctype is c_double else np.uint32))
        offsets.append(getattr(LimitPatch, name).offset)
    return np.dtype({"names": names, "formats": formats, "offsets": offsets,
                     "itemsize": ctypes.sizeof(LimitPatch)})


def _bernstein(x):
    """(n, 4) cubic Bernstein weights B_0..B_3 at x (n,)."""
    x = np.asarray(x, dtype=np.float64).reshape(-1)
    y = 1.0 - x
    return np.stack([y ** 3, 3.0 * x * y * y, 3.0 * x * x * y, x ** 3], axis=1)


class LimitPatches(Handle):
    """The limit surface of a cage as bicubic Bezier patches (see the module doc)."""

    _release_name = "cagekit_limit_patches_release"
    _functions = lib
    _kind = "limit patches"

    def __init__(self, cage: Cage, tolerance: float = _D["tolerance"], max_depth: int = _D["max_depth"],
                 threads: int = _D["threads"]) -> None:
        """tolerance: the largest distance allowed between an approximated patch and the limit
        surface, as a fraction of the bounding-box diagonal of the cage's control points (> 0);
        max_depth: how often a square that is not one polynomial may be split into 4 (0..12);
        threads: worker threads (0: all hardware threads; the patches do not depend on it). Bad
        values raise InvalidArgumentError with the SDK's message; more than 2^20 patches
        LimitExceededError. Long operation (progress stage "limit patches", cancel)."""
        options = LimitPatchOptions.new(tolerance=float(tolerance), max_depth=int(max_depth), threads=int(threads))
        out = ctypes.c_void_p()
        cage._context._call(lib.cagekit_limit_patches_create, cage._handle, ctypes.byref(options),
                            ctypes.byref(out), outs=[(out, self._release())])
        Handle.__init__(self, out.value, cage._context)
        self._records: Optional[np.ndarray] = None
        self._info: Optional[Record] = None

    @property
    def info(self) -> Record:
        """Record: patch_count, exact_count, approximated_count, over_tolerance_count, max_error
        (model units), max_error_rel (of bbox_diagonal), bbox_diagonal (of the control points),
        tolerance (the absolute one: options.tolerance * bbox_diagonal)."""
        if self._info is None:
            info = LimitPatchInfo.new()
            self._context._call(lib.cagekit_limit_patches_get_info, self._handle, ctypes.byref(info))
            self._info = from_struct(info, "LimitPatchInfo")
        return self._info

    def __len__(self) -> int:
        return self.info.patch_count

    def records(self, first: int = 0, count: Optional[int] = None) -> np.ndarray:
        """Patches [first, first + count) as a numpy record array laid out as cagekit_limit_patch
        (fields ptex_face, cage_face, u0, v0, u1, v1, exact, reserved, error, control_points (48,)).
        A range not inside [0, patch_count) raises InvalidArgumentError."""
        total = self.info.patch_count
        first = int(first)
        count = max(total - first, 0) if count is None else int(count)
        if first < 0 or count < 0 or first + count > total:
            raise InvalidArgumentError("patches [%d, %d) are not inside [0, %d)" % (first, first + count, total))
        return self._all()[first:first + count].copy()

    def _all(self) -> np.ndarray:
        """Every patch, read once (cagekit_limit_patches_get, two-call) and kept."""
        if self._records is None:
            count = ctypes.c_uint32()
            self._context._call(lib.cagekit_limit_patches_get, self._handle, 0, ctypes.byref(count), None)
            out = np.zeros(count.value, dtype=_patch_dtype())
            self._context._call(lib.cagekit_limit_patches_get, self._handle, count.value, ctypes.byref(count),
                                _lib.address(out))
            self._records = out
        return self._records

    @property
    def control_points(self) -> np.ndarray:
        """(N, 4, 4, 3) float64: [k, i, j] is control point (i, j) of patch k, whose weight is
        B_i(s) B_j(t) (i along s, the ptex u direction)."""
        raw = self._all()["control_points"].reshape(-1, 4, 4, 3)  # C order: [k, j, i]
        return np.ascontiguousarray(raw.transpose(0, 2, 1, 3))

    @property
    def domains(self) -> np.ndarray:
        """(N, 4) float64: u0, v0, u1, v1 of each patch in its ptex face."""
        r = self._all()
        return np.stack([r["u0"], r["v0"], r["u1"], r["v1"]], axis=1)

    @property
    def ptex_faces(self) -> np.ndarray:
        return self._all()["ptex_face"].copy()

    @property
    def cage_faces(self) -> np.ndarray:
        return self._all()["cage_face"].copy()

    @property
    def exact(self) -> np.ndarray:
        """(N,) bool: True where the patch is the limit surface itself."""
        return self._all()["exact"] != 0

    @property
    def errors(self) -> np.ndarray:
        """(N,) float64: measured largest distance of each patch to the limit surface, model units
        (rounding level for exact patches)."""
        return self._all()["error"].copy()

    def ptex_locations(self, patches: npt.ArrayLike, st: npt.ArrayLike) -> Tuple[np.ndarray, np.ndarray]:
        """(ptex faces (n,), (n, 2) ptex (u, v)) of Bezier parameters st (n, 2) of patches (n,) or one."""
        patches = np.atleast_1d(np.asarray(patches, dtype=np.int64))
        st = np.asarray(st, dtype=np.float64).reshape(-1, 2)
        if patches.size == 1 and st.shape[0] > 1:
            patches = np.repeat(patches, st.shape[0])
        if patches.size != st.shape[0]:
            raise ValueError("cagekit: %d patches for %d (s, t) pairs" % (patches.size, st.shape[0]))
        d = self.domains[patches]
        uv = np.stack([d[:, 0] + st[:, 0] * (d[:, 2] - d[:, 0]), d[:, 1] + st[:, 1] * (d[:, 3] - d[:, 1])], axis=1)
        return self.ptex_faces[patches], uv

    def evaluate(self, patches: npt.ArrayLike, st: npt.ArrayLike) -> np.ndarray:
        """(n, 3) points of the Bezier patches `patches` ((n,) or one index) at st (n, 2)."""
        patches = np.atleast_1d(np.asarray(patches, dtype=np.int64))
        st = np.asarray(st, dtype=np.float64).reshape(-1, 2)
        if patches.size == 1 and st.shape[0] > 1:
            patches = np.repeat(patches, st.shape[0])
        if patches.size != st.shape[0]:
            raise ValueError("cagekit: %d patches for %d (s, t) pairs" % (patches.size, st.shape[0]))
        cp = self.control_points[patches]                      # (n, 4, 4, 3)
        bs, bt = _bernstein(st[:, 0]), _bernstein(st[:, 1])    # (n, 4) each
        return np.einsum("ni,nj,nijc->nc", bs, bt, cp)


def limit_patches(cage: Cage, tolerance: float = _D["tolerance"], max_depth: int = _D["max_depth"],
                  threads: int = _D["threads"]) -> LimitPatches:
    """LimitPatches(cage, tolerance, max_depth, threads)."""
    return LimitPatches(cage, tolerance=tolerance, max_depth=max_depth, threads=threads)
