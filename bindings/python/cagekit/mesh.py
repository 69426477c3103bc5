# SPDX-License-Identifier: GPL-3.0-or-later
"""Mesh: an indexed polygon mesh (cagekit_mesh), with numpy arrays in and out.

    mesh = cagekit.Mesh.from_arrays(positions, faces)   # (N,3) float64/float32, faces as below
    mesh.positions                                      # (N,3) float64 copy
    mesh.faces                                          # a list of uint32 arrays, one per face
    mesh.validate()                                     # raises InvalidMeshError naming the problem
    fixed, report = mesh.repair()
    data = mesh.to_bytes("ply"); again = cagekit.Mesh.from_bytes(data)

faces: a (F, k) integer array; a list of index lists (polygons of any size); a tuple
(face_sizes, flat_indices); or flat indices with face_sizes=. The content is not validated at
creation (so validate() can report it and repair() fix it).
"""
from __future__ import annotations

import ctypes
import enum
from typing import TYPE_CHECKING, Any, List, Optional, Tuple, Union

from . import _arrays, _formats, _lib, _typing
from ._errors import InvalidMeshError
from ._formats import FormatLike
from ._handle import Handle
from ._numpy import np, npt
from ._records import Record, from_struct
from ._typing import Buffer, StrPath
from .context import Context, resolve

if TYPE_CHECKING:
    from . import cage as _cage_module
else:
    _cage_module = _typing.loaded("cagekit.cage")  # cage.py imports this module


# CAGEKIT_REPAIR_OPTIONS_INIT, written once (in _lib).
_REPAIR = _lib.RepairOptions.defaults()


class MeshIssue(enum.IntEnum):
    INDEX_OUT_OF_RANGE = 0
    NON_FINITE_POSITION = 1
    DEGENERATE_FACE = 2
    DUPLICATE_FACE = 3
    NON_MANIFOLD_EDGE = 4
    NON_MANIFOLD_VERTEX = 5
    INCONSISTENT_ORIENTATION = 6
    UNREFERENCED_VERTEX = 7  # a warning only


class RepairSteps(enum.IntFlag):
    DROP_INVALID_FACES = 1 << 0
    DROP_DEGENERATE_FACES = 1 << 1
    DROP_DUPLICATE_FACES = 1 << 2
    SPLIT_NON_MANIFOLD = 1 << 3
    ORIENT = 1 << 4
    REMOVE_UNREFERENCED = 1 << 5
    WELD = 1 << 6
    DEFAULT = 0x1f | (1 << 6)


def read_positions(obj, get_mesh_ptr, dtype=None):
    """Positions of a mesh handle through the two-call idiom."""
    dtype = np.float64 if dtype is None else np.dtype(dtype)
    kind = _arrays.FLOAT32 if dtype == np.float32 else _arrays.FLOAT64
    if dtype not in (np.float32, np.float64):
        raise ValueError("cagekit: positions are float32 or float64")
    ctx, fn = obj._context, _lib.lib.cagekit_mesh_get_positions
    count = ctypes.c_uint32()
    ctx._call(fn, get_mesh_ptr, kind, 0, ctypes.byref(count), None)
    out = np.empty((count.value, 3), dtype=dtype)
    ctx._call(fn, get_mesh_ptr, kind, count.value, ctypes.byref(count), _lib.address(out))
    return out


def read_faces(obj, mesh_ptr, fn=None):
    """(face sizes, flat indices) as uint32 arrays through the two-call idiom."""
    ctx = obj._context
    fn = fn or _lib.lib.cagekit_mesh_get_faces
    faces, indices = ctypes.c_uint32(), ctypes.c_uint64()
    ctx._call(fn, mesh_ptr, 0, ctypes.byref(faces), None, 0, ctypes.byref(indices), None)
    sizes = np.empty(faces.value, dtype=np.uint32)
    flat = np.empty(indices.value, dtype=np.uint32)
    ctx._call(fn, mesh_ptr, faces.value, ctypes.byref(faces), _lib.address(sizes), indices.value,
              ctypes.byref(indices), _lib.address(flat))
    return sizes, flat


class Mesh(Handle, _formats.Writable):
    """An indexed polygon mesh. Reads are thread-safe; a Mesh is immutable once made."""

    _release_name = "cagekit_mesh_release"
    _kind = "mesh"
    _write_functions = ("cagekit_mesh_write_file", "cagekit_mesh_write_memory")

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        raise TypeError("use Mesh.from_arrays, Mesh.read or Mesh.from_bytes")

    @classmethod
    def _make(cls, context: Any, fn: Any, *args: Any) -> Mesh:
        return super()._make(resolve(context), fn, *args)

    # --- creation ----------------------------------------------------------------------------
    @classmethod
    def from_arrays(cls, positions: npt.ArrayLike, faces: Optional[npt.ArrayLike] = None, *,
                    face_sizes: Optional[npt.ArrayLike] = None, context: Optional[Context] = None) -> Mesh:
        """A mesh copied from numpy arrays (see the module doc for the face forms)."""
        ctx = resolve(context)
        pos, kind = _arrays.positions(positions)
        sizes, uniform, flat, face_count = _arrays.faces(faces, face_sizes)
        desc = _lib.MeshDesc.new(vertex_count=pos.shape[0], positions=_lib.address(pos), position_type=kind,
                                 face_count=face_count, face_sizes=_lib.address(sizes),
                                 uniform_face_size=uniform, face_indices=_lib.address(flat))
        return cls._make(ctx, _lib.lib.cagekit_mesh_create, ctx._handle, ctypes.byref(desc))

    @classmethod
    def read(cls, path: StrPath, format: FormatLike = "auto", context: Optional[Context] = None) -> Mesh:
        """Reads OBJ, PLY, OFF, Draco or STL (format 'auto': by extension). Tags are ignored."""
        ctx = resolve(context)
        return cls._make(ctx, _lib.lib.cagekit_mesh_read_file, ctx._handle, _formats.path_bytes(path),
                         int(_formats.file_format(format)))

    @classmethod
    def from_bytes(cls, data: Buffer, format: FormatLike = "auto", context: Optional[Context] = None) -> Mesh:
        """Decodes a file held in memory (format 'auto': sniffed from the content)."""
        ctx = resolve(context)
        keep, address, size = _formats.input_bytes(data)
        return cls._make(ctx, _lib.lib.cagekit_mesh_read_memory, ctx._handle, address, size,
                         int(_formats.file_format(format)))

    # --- read-back ---------------------------------------------------------------------------
    def counts(self) -> Tuple[int, int, int]:
        """(vertex count, face count, total face indices)."""
        v, f, i = ctypes.c_uint32(), ctypes.c_uint32(), ctypes.c_uint64()
        self._context._call(_lib.lib.cagekit_mesh_get_counts, self._handle, ctypes.byref(v), ctypes.byref(f),
                            ctypes.byref(i))
        return v.value, f.value, i.value

    @property
    def vertex_count(self) -> int:
        return self.counts()[0]

    @property
    def face_count(self) -> int:
        return self.counts()[1]

    @property
    def positions(self) -> np.ndarray:
        """(N, 3) float64 copy of the positions."""
        return read_positions(self, self._handle)

    def get_positions(self, dtype: npt.DTypeLike = None) -> np.ndarray:
        """Positions as float64 (default) or float32."""
        return read_positions(self, self._handle, dtype)

    def face_arrays(self) -> Tuple[np.ndarray, np.ndarray]:
        """(face_sizes, flat_indices) uint32 arrays."""
        return read_faces(self, self._handle)

    @property
    def faces(self) -> List[np.ndarray]:
        """A list with one 1-D uint32 array of vertex indices per face, for every mesh (triangles,
        quads or mixed polygons alike; [] without faces). np.array(mesh.faces) makes the (F, k)
        array of a mesh whose faces all have k vertices; face_arrays() is the flat form without
        an object per face (for large meshes)."""
        return _arrays.split_faces(*self.face_arrays())

    # --- checks ------------------------------------------------------------------------------
    def validate(self, check: bool = True) -> Record:
        """Checks every MeshIssue. Returns a record (valid, issue_flags, issue_counts, issues: a
        dict MeshIssue -> count, message). check=True raises InvalidMeshError (with the SDK's
        message naming each problem, and the record as .report) when the mesh is invalid."""
        report = _lib.ValidationReport.new()
        message = ""
        try:
            self._context._call(_lib.lib.cagekit_mesh_validate, self._handle, ctypes.byref(report))
        except InvalidMeshError as e:
            message = e.message
            record = _validation_record(report, message)
            if check:
                e.report = record
                raise
            return record
        return _validation_record(report, message)

    def repair(self, steps: Union[RepairSteps, int] = RepairSteps(_REPAIR["steps"]),
               weld_tolerance: float = _REPAIR["weld_tolerance"]) -> Tuple[Mesh, Record]:
        """A repaired copy (this mesh is unchanged) and the repair report. Long operation."""
        options = _lib.RepairOptions.new(steps=int(steps), weld_tolerance=float(weld_tolerance))
        report = _lib.RepairReport.new()
        out = ctypes.c_void_p()
        self._context._call(_lib.lib.cagekit_mesh_repair, self._handle, ctypes.byref(options), ctypes.byref(out),
                            ctypes.byref(report), outs=[(out, self._release())])
        return Mesh._wrap(out.value, self._context), from_struct(report, "RepairReport")

    def info(self) -> Record:
        """Statistics: vertices, faces, edges, triangles, quads, boundary loops, genus, bbox, ..."""
        info = _lib.MeshInfo.new()
        self._context._call(_lib.lib.cagekit_mesh_get_info, self._handle, ctypes.byref(info))
        return from_struct(info, "MeshInfo")

    def measure_error(self, approximation: Union[Mesh, _cage_module.Cage]) -> Record:
        """Distances from this (input) mesh to `approximation` (a Mesh, or a Cage's control mesh),
        relative to this mesh's bbox diagonal: hausdorff_rel, hausdorff_sym_rel, mean_rel."""
        other = approximation.mesh() if hasattr(approximation, "mesh") else approximation
        try:
            error = _lib.ApproximationError.new()
            self._context._call(_lib.lib.cagekit_mesh_measure_error, self._handle, other._handle,
                                ctypes.byref(error))
            return from_struct(error, "ApproximationError")
        finally:
            if other is not approximation:
                other.close()


def _validation_record(report, message):
    record = from_struct(report, "ValidationReport")
    record.valid = bool(report.valid)
    record.issues = {issue: int(report.issue_counts[issue]) for issue in MeshIssue if report.issue_counts[issue]}
    record.message = message
    return record
