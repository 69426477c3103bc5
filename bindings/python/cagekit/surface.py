# SPDX-License-Identifier: GPL-3.0-or-later
"""Surface: evaluation of a cage's limit surface at ptex locations (face, u, v).

A quad of the cage is one ptex face with (u, v) in [0, 1]^2; any other n-gon is n ptex faces,
one per corner (ptex_face(cage_face, corner)). Immutable: any number of threads may evaluate.
"""
from __future__ import annotations

import ctypes
from typing import Any, Optional, Tuple

from . import _arrays, _lib
from ._handle import Handle
from ._numpy import np, npt
from ._records import Record

_DERIVATIVES = ("position", "du", "dv", "duu", "duv", "dvv")


class Surface(Handle):
    _release_name = "cagekit_surface_release"
    _kind = "surface"

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        raise TypeError("use Cage.surface()")

    def counts(self) -> Tuple[int, int]:
        """(ptex face count, control vertex count)."""
        faces, controls = ctypes.c_uint32(), ctypes.c_uint32()
        self._context._call(_lib.lib.cagekit_surface_get_counts, self._handle, ctypes.byref(faces),
                            ctypes.byref(controls))
        return faces.value, controls.value

    def ptex_face(self, cage_face: int, corner: int = 0) -> int:
        out = ctypes.c_uint32()
        self._context._call(_lib.lib.cagekit_surface_get_ptex_face, self._handle, int(cage_face), int(corner),
                            ctypes.byref(out))
        return out.value

    @staticmethod
    def _locations(faces, uv):
        faces = np.atleast_1d(np.asarray(faces))
        uv = np.asarray(uv, dtype=np.float64).reshape(-1, 2)
        if faces.size == 1 and uv.shape[0] > 1:
            faces = np.repeat(faces, uv.shape[0])
        if faces.size != uv.shape[0]:
            raise ValueError("cagekit: %d faces for %d (u, v) pairs" % (faces.size, uv.shape[0]))
        locations = np.zeros(faces.size, dtype=np.dtype([("face", np.uint32), ("u", np.float64),
                                                          ("v", np.float64)], align=True))
        assert locations.dtype.itemsize == ctypes.sizeof(_lib.SurfaceLocation)
        locations["face"] = _arrays.indices(faces, "faces")
        locations["u"], locations["v"] = uv[:, 0], uv[:, 1]
        return locations

    def evaluate(self, faces: npt.ArrayLike, uv: npt.ArrayLike,
                 control_positions: Optional[npt.ArrayLike] = None) -> Record:
        """Evaluates at ptex faces `faces` ((n,) or one face) and parameters `uv` ((n, 2)).
        control_positions: None (the cage's) or moved control points (M, 3). Returns a record
        of (n, 3) arrays: position, du, dv, duu, duv, dvv."""
        locations = self._locations(faces, uv)
        control = None
        if control_positions is not None:
            control = _arrays.control(control_positions, self.counts()[1], "control_positions")
        points = np.empty((locations.size, 6, 3))
        self._context._call(_lib.lib.cagekit_surface_evaluate, self._handle, _lib.address(control),
                            locations.size, _lib.address(locations), _lib.address(points))
        return Record("SurfacePoints", **{name: points[:, k, :] for k, name in enumerate(_DERIVATIVES)})

    def evaluate_basis(self, face: int, u: float, v: float) -> Record:
        """The basis functions non-zero at (face, u, v): record of indices (K,) and weights
        w, wu, wv, wuu, wuv, wvv (K,), so that position = w @ control[indices]."""
        location = _lib.SurfaceLocation(int(face), float(u), float(v))
        fn, count = _lib.lib.cagekit_surface_evaluate_basis, ctypes.c_uint32()
        self._context._call(fn, self._handle, ctypes.byref(location), 0, ctypes.byref(count), *([None] * 7))
        n = count.value
        indices = np.empty(n, dtype=np.uint32)
        weights = np.empty((6, n))
        self._context._call(fn, self._handle, ctypes.byref(location), n, ctypes.byref(count),
                            _lib.address(indices), *[_lib.address(weights[k]) for k in range(6)])
        names = ("w", "wu", "wv", "wuu", "wuv", "wvv")
        return Record("Basis", indices=indices, **{name: weights[k] for k, name in enumerate(names)})
