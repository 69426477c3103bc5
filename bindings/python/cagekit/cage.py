# SPDX-License-Identifier: GPL-3.0-or-later
"""Cage: a Catmull-Clark control mesh with crease, corner and hole tags (cagekit_cage).

    cage = cagekit.Cage.from_arrays(positions, quads, creases=edges)   # edges: (C, 2) vertex pairs
    fine = cage.subdivide(levels=2, limit_positions=True)
    points, normals = cage.limit_points()
    surface = cage.surface()                                            # evaluation at (face, u, v)

Sharpness: SHARP (10.0) and above is an infinitely sharp tag (the thesis's binary crease);
values in (0, 10) are OpenSubdiv semi-sharp creases; 0 removes a tag.
"""
from __future__ import annotations

import ctypes
import enum
from typing import Any, List, Optional, Tuple, Union

from . import _arrays, _formats, _lib
from ._formats import FormatLike
from ._handle import Handle
from ._numpy import np, npt
from ._records import Record, from_struct
from ._typing import Buffer, StrPath
from .context import Context, resolve
from .fit import fit as _fit
from .mesh import Mesh, read_faces, read_positions
from .surface import Surface

SHARP = _lib.SHARP
# CAGEKIT_*_OPTIONS_INIT of the structs filled here, written once (in _lib).
_SUBDIVIDE = _lib.SubdivideOptions.defaults()
_SURFACE = _lib.SurfaceOptions.defaults()


class BoundaryRule(enum.IntEnum):
    EDGES_ONLY = 0             # boundary edges sharp, boundary vertices not pinned (default)
    EDGES_AND_CORNERS = 1      # also pin boundary vertices with two incident edges


def _sharpness(values, count, name):
    if values is None:
        return None
    a = np.ascontiguousarray(np.broadcast_to(np.asarray(values, dtype=np.float32), (count,)))
    return a


class Cage(Handle, _formats.Writable):
    """A control cage. Tag setters modify it (one thread at a time); everything else reads."""

    _release_name = "cagekit_cage_release"
    _kind = "cage"
    _write_functions = ("cagekit_cage_write_file", "cagekit_cage_write_memory")

    def __init__(self, mesh: Mesh) -> None:
        """A cage whose control mesh is a copy of `mesh` (which must be valid: InvalidMeshError
        names the first problem otherwise), without tags."""
        out = ctypes.c_void_p()
        mesh._context._call(_lib.lib.cagekit_cage_create, mesh._handle, ctypes.byref(out),
                            outs=[(out, self._release())])
        Handle.__init__(self, out.value, mesh._context)

    @classmethod
    def from_arrays(cls, positions: npt.ArrayLike, faces: Optional[npt.ArrayLike], *,
                    face_sizes: Optional[npt.ArrayLike] = None, creases: Optional[npt.ArrayLike] = None,
                    crease_sharpness: Optional[npt.ArrayLike] = None, corners: Optional[npt.ArrayLike] = None,
                    corner_sharpness: Optional[npt.ArrayLike] = None, holes: Optional[npt.ArrayLike] = None,
                    boundary_rule: Union[BoundaryRule, int, None] = None, context: Optional[Context] = None) -> Cage:
        """A cage from numpy arrays: faces as for Mesh.from_arrays, creases (C, 2) vertex pairs,
        corners vertex indices, holes face indices."""
        with Mesh.from_arrays(positions, faces, face_sizes=face_sizes, context=context) as mesh:
            cage = cls(mesh)
        try:
            if creases is not None:
                cage.set_creases(creases, crease_sharpness)
            if corners is not None:
                cage.set_corners(corners, corner_sharpness)
            if holes is not None:
                cage.set_holes(holes)
            if boundary_rule is not None:
                cage.boundary_rule = boundary_rule  # type: ignore[assignment]  # the setter takes ints too
        except BaseException:
            cage.close()
            raise
        return cage

    @classmethod
    def read(cls, path: StrPath, format: FormatLike = "auto", context: Optional[Context] = None) -> Cage:
        """Reads a cage; OBJ (`t crease/corner/hole` lines) and Draco keep tags."""
        ctx = resolve(context)
        return cls._make(ctx, _lib.lib.cagekit_cage_read_file, ctx._handle, _formats.path_bytes(path),
                         int(_formats.file_format(format)))

    @classmethod
    def from_bytes(cls, data: Buffer, format: FormatLike = "auto", context: Optional[Context] = None) -> Cage:
        ctx = resolve(context)
        keep, address, size = _formats.input_bytes(data)
        return cls._make(ctx, _lib.lib.cagekit_cage_read_memory, ctx._handle, address, size,
                         int(_formats.file_format(format)))

    # --- control mesh ------------------------------------------------------------------------
    def mesh(self) -> Mesh:
        """A Mesh holding a copy of the control mesh."""
        return Mesh._make(self._context, _lib.lib.cagekit_cage_get_mesh, self._handle)

    def _control_mesh(self):
        """(positions, face sizes, flat indices), read from C on the first call (one copy of the
        control mesh) and kept. No method changes a cage's control mesh (the tag setters change
        tags only; subdivide, fit and remesh make new cages), so the arrays never go stale; a
        method that changed positions or faces would have to set _mesh_arrays to None."""
        self._handle  # a closed cage raises ValueError, cached arrays or not
        arrays = getattr(self, "_mesh_arrays", None)
        if arrays is None:
            with self.mesh() as m:
                arrays = (read_positions(m, m._handle),) + read_faces(m, m._handle)
            self._mesh_arrays = arrays
        return arrays

    @property
    def positions(self) -> np.ndarray:
        """(N, 3) float64 control points: a copy (the caller may change it) of the array read once,
        on the first access to positions, faces or face_arrays(), and cached, since a cage's
        positions never change; repeated accesses make no C call."""
        return self._control_mesh()[0].copy()

    @property
    def faces(self) -> List[np.ndarray]:
        """A list with one 1-D uint32 array of vertex indices per face, as Mesh.faces, from the
        cached control mesh (see positions)."""
        return _arrays.split_faces(*(a.copy() for a in self._control_mesh()[1:]))

    def face_arrays(self) -> Tuple[np.ndarray, np.ndarray]:
        """(face_sizes, flat_indices) uint32 copies, from the cached control mesh (see positions)."""
        _, sizes, flat = self._control_mesh()
        return sizes.copy(), flat.copy()

    def info(self) -> Record:
        """Control-mesh statistics plus tag counts (creases, corners, holes)."""
        info = _lib.MeshInfo.new()
        self._context._call(_lib.lib.cagekit_cage_get_info, self._handle, ctypes.byref(info))
        return from_struct(info, "MeshInfo")

    # --- tags --------------------------------------------------------------------------------
    def set_creases(self, vertex_pairs: npt.ArrayLike, sharpness: Optional[npt.ArrayLike] = None) -> None:
        """Replaces the crease tags: (C, 2) vertex pairs (edges of the control mesh), sharpness
        per crease or one value (None: SHARP). InvalidArgumentError names a pair that is no edge."""
        pairs = _arrays.indices(vertex_pairs, "crease vertex pairs")
        if pairs.size % 2:
            raise ValueError("cagekit: crease vertex pairs must have shape (C, 2)")
        count = pairs.size // 2
        sharp = _sharpness(sharpness, count, "crease sharpness")
        self._context._call(_lib.lib.cagekit_cage_set_creases, self._handle, count, _lib.address(pairs),
                            _lib.address(sharp))

    @property
    def creases(self) -> Tuple[np.ndarray, np.ndarray]:
        """((C, 2) uint32 vertex pairs, (C,) float32 sharpness)."""
        fn, count = _lib.lib.cagekit_cage_get_creases, ctypes.c_uint32()
        self._context._call(fn, self._handle, 0, ctypes.byref(count), None, None)
        pairs = np.empty((count.value, 2), dtype=np.uint32)
        sharp = np.empty(count.value, dtype=np.float32)
        self._context._call(fn, self._handle, count.value, ctypes.byref(count), _lib.address(pairs),
                            _lib.address(sharp))
        return pairs, sharp

    def set_corners(self, vertices: npt.ArrayLike, sharpness: Optional[npt.ArrayLike] = None) -> None:
        verts = _arrays.indices(vertices, "corner vertices")
        sharp = _sharpness(sharpness, verts.size, "corner sharpness")
        self._context._call(_lib.lib.cagekit_cage_set_corners, self._handle, verts.size, _lib.address(verts),
                            _lib.address(sharp))

    @property
    def corners(self) -> Tuple[np.ndarray, np.ndarray]:
        """((K,) uint32 vertices, (K,) float32 sharpness)."""
        fn, count = _lib.lib.cagekit_cage_get_corners, ctypes.c_uint32()
        self._context._call(fn, self._handle, 0, ctypes.byref(count), None, None)
        verts = np.empty(count.value, dtype=np.uint32)
        sharp = np.empty(count.value, dtype=np.float32)
        self._context._call(fn, self._handle, count.value, ctypes.byref(count), _lib.address(verts),
                            _lib.address(sharp))
        return verts, sharp

    def set_holes(self, faces: npt.ArrayLike) -> None:
        f = _arrays.indices(faces, "hole faces")
        self._context._call(_lib.lib.cagekit_cage_set_holes, self._handle, f.size, _lib.address(f))

    @property
    def holes(self) -> np.ndarray:
        """(H,) uint32 hole faces."""
        fn, count = _lib.lib.cagekit_cage_get_holes, ctypes.c_uint32()
        self._context._call(fn, self._handle, 0, ctypes.byref(count), None)
        faces = np.empty(count.value, dtype=np.uint32)
        self._context._call(fn, self._handle, count.value, ctypes.byref(count), _lib.address(faces))
        return faces

    @property
    def boundary_rule(self) -> BoundaryRule:
        rule = ctypes.c_int()
        self._context._call(_lib.lib.cagekit_cage_get_boundary_rule, self._handle, ctypes.byref(rule))
        return BoundaryRule(rule.value)

    @boundary_rule.setter
    def boundary_rule(self, rule: Union[BoundaryRule, int]) -> None:
        self._context._call(_lib.lib.cagekit_cage_set_boundary_rule, self._handle, int(rule))

    # --- subdivision and the limit surface ----------------------------------------------------
    def subdivide(self, levels: int = _SUBDIVIDE["levels"],
                  limit_positions: bool = bool(_SUBDIVIDE["limit_positions"])) -> Cage:
        """A new cage refined `levels` times (0..8), tags refined; limit_positions moves the
        vertices onto the limit surface. Long operation (progress, cancel)."""
        options = _lib.SubdivideOptions.new(levels=int(levels), limit_positions=1 if limit_positions else 0)
        return Cage._make(self._context, _lib.lib.cagekit_cage_subdivide, self._handle, ctypes.byref(options))

    def limit_points(self) -> Tuple[np.ndarray, np.ndarray]:
        """((N, 3) limit positions, (N, 3) unit normals) of the control vertices."""
        fn, count = _lib.lib.cagekit_cage_get_limit_points, ctypes.c_uint32()
        self._context._call(fn, self._handle, 0, ctypes.byref(count), None, None)
        pos = np.empty((count.value, 3))
        nrm = np.empty((count.value, 3))
        self._context._call(fn, self._handle, count.value, ctypes.byref(count), _lib.address(pos),
                            _lib.address(nrm))
        return pos, nrm

    def surface(self, isolation_level: int = _SURFACE["isolation_level"],
                sharp_isolation_level: int = _SURFACE["sharp_isolation_level"]) -> Surface:
        """A limit-surface evaluator (a snapshot of this cage). Long operation."""
        options = _lib.SurfaceOptions.new(isolation_level=int(isolation_level),
                                          sharp_isolation_level=int(sharp_isolation_level))
        return Surface._make(self._context, _lib.lib.cagekit_surface_create, self._handle, ctypes.byref(options))

    def fit(self, scan: Mesh, **options: Any) -> Tuple[Cage, Record]:
        """cagekit.fit(self, scan, **options): (fitted Cage, FitReport)."""
        return _fit(self, scan, **options)
