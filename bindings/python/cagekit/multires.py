# SPDX-License-Identifier: GPL-3.0-or-later
"""Multiresolution editing (thesis ch. 8): bind a scan to a cage's limit surface, then rebuild
it, details kept, for moved control points.

    binding = cagekit.bind(fitted_cage, scan, sharp_angle_degrees=-1)   # long: progress "bind"
    binding.save("scan.ckb"); binding = cagekit.Binding.load("scan.ckb")
    deformer = cagekit.CpuDeformer(binding)
    control = binding.control_points()          # (C, 3) float64: the cage's vertices
    control[7] += (0, 0, 0.1)
    positions, normals = deformer.deform(control)
    positions, normals = deformer.update(control, moved=[7])    # only the support of point 7

A Binding is immutable (any thread); a CpuDeformer is used by one thread at a time, and
separate deformers run in parallel from several Python threads (the GIL is released).
"""
from __future__ import annotations

import ctypes
import enum
from typing import Any, Dict, Optional, Tuple, Union

from . import _arrays, _formats, _lib
from ._handle import Handle
from ._numpy import np, npt
from ._records import Record, enum_value as _enum, from_struct
from ._typing import Buffer, StrPath
from .cage import Cage
from .context import Context, resolve
from .mesh import Mesh


class DisplacementMode(enum.IntEnum):
    NORMAL = 0       # the thesis: displacement along the surface normal
    LOCAL_FRAME = 1  # the whole offset in the surface's orthonormal frame


class NormalMode(enum.IntEnum):
    APPROXIMATE = 0  # from S_u, S_v (8.11)-(8.12)
    EXACT = 1        # (8.4)-(8.7): needs a binding made with exact_normals=True


class Binding(Handle):
    """A scan bound to a cage's limit surface."""

    _release_name = "cagekit_binding_release"
    _kind = "binding"

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        raise TypeError("use cagekit.bind, Binding.load or Binding.from_bytes")

    @classmethod
    def load(cls, path: StrPath, context: Optional[Context] = None, threads: int = 0) -> Binding:
        """Reads a .ckb file (hostile bytes give ParseError with the offset; long operation)."""
        ctx = resolve(context)
        return cls._make(ctx, _lib.lib.cagekit_binding_read_file, ctx._handle, _formats.path_bytes(path),
                         int(threads))

    @classmethod
    def from_bytes(cls, data: Buffer, context: Optional[Context] = None, threads: int = 0) -> Binding:
        ctx = resolve(context)
        keep, address, size = _formats.input_bytes(data)
        return cls._make(ctx, _lib.lib.cagekit_binding_read_memory, ctx._handle, address, size, int(threads))

    def save(self, path: StrPath) -> None:
        """Writes a .ckb file atomically."""
        self._context._call(_lib.lib.cagekit_binding_write_file, self._handle, _formats.path_bytes(path))

    def to_bytes(self) -> bytes:
        blob = ctypes.c_void_p()
        self._context._call(_lib.lib.cagekit_binding_write_memory, self._handle, ctypes.byref(blob),
                            outs=[(blob, "cagekit_blob_release")])
        return _formats.blob_bytes(blob)

    def info(self) -> Record:
        """Record: vertex_count, control_count, basis_entries, max_sideways_residual,
        bbox_diagonal, has_exact_normals, scan_vertex_count, has_sector_split, ..."""
        info = _lib.BindingInfo.new()
        self._context._call(_lib.lib.cagekit_binding_get_info, self._handle, ctypes.byref(info))
        record = from_struct(info, "BindingInfo")
        record.has_exact_normals = bool(record.has_exact_normals)
        record.has_sector_split = bool(record.has_sector_split)
        return record

    def cage(self) -> Cage:
        """A copy of the cage the binding was made on."""
        return Cage._make(self._context, _lib.lib.cagekit_binding_get_cage, self._handle)

    def control_points(self) -> np.ndarray:
        """(C, 3) float64 control points of the bound cage (the undeformed state)."""
        with self.cage() as cage:
            return cage.positions

    def vertex_sources(self) -> np.ndarray:
        """For each bound vertex, the scan vertex it copies (identity without a sector split)."""
        fn, count = _lib.lib.cagekit_binding_get_vertex_sources, ctypes.c_uint32()
        self._context._call(fn, self._handle, 0, ctypes.byref(count), None)
        out = np.empty(count.value, dtype=np.uint32)
        self._context._call(fn, self._handle, count.value, ctypes.byref(count), _lib.address(out))
        return out

    def deformer_vertex_order(self) -> np.ndarray:
        """Renumbering of the scan's vertices in the order the CPU deformer writes them (uint32:
        order[k] = the scan vertex that becomes vertex k). Hosts that may renumber their scan
        apply it once and bind again: the deformer's writes become nearly sequential (faster full
        frames); the deformed shape is the same either way."""
        fn, count = _lib.lib.cagekit_binding_get_deformer_vertex_order, ctypes.c_uint32()
        self._context._call(fn, self._handle, 0, ctypes.byref(count), None)
        out = np.empty(count.value, dtype=np.uint32)
        self._context._call(fn, self._handle, count.value, ctypes.byref(count), _lib.address(out))
        return out

    def face_arrays(self) -> Optional[Tuple[np.ndarray, np.ndarray]]:
        """(face_sizes, flat_indices) over the bound vertices with a sector split; None without
        one (the scan's own faces apply)."""
        fn = _lib.lib.cagekit_binding_get_faces
        faces, indices = ctypes.c_uint32(), ctypes.c_uint64()
        self._context._call(fn, self._handle, 0, ctypes.byref(faces), None, 0, ctypes.byref(indices), None)
        if faces.value == 0:
            return None
        sizes = np.empty(faces.value, dtype=np.uint32)
        flat = np.empty(indices.value, dtype=np.uint32)
        self._context._call(fn, self._handle, faces.value, ctypes.byref(faces), _lib.address(sizes),
                            indices.value, ctypes.byref(indices), _lib.address(flat))
        return sizes, flat


_BIND = _lib.BindOptions.defaults()  # CAGEKIT_BIND_OPTIONS_INIT, written once (in _lib.BindOptions)


def bind(cage: Cage, scan: Mesh, mode: Union[DisplacementMode, int, str] = DisplacementMode(_BIND["mode"]),
         exact_normals: bool = bool(_BIND["exact_normals"]), threads: int = _BIND["threads"],
         sharp_angle_degrees: float = _BIND["sharp_angle_degrees"]) -> Binding:
    """Binds every vertex of `scan` to the limit surface of `cage` (usually fitted to it first).
    mode: 'normal' or 'local_frame'; sharp_angle_degrees >= 0 binds one copy of a vertex per
    smooth sector at sharp edges. Long operation (progress "bind", cancel)."""
    options = _lib.BindOptions.new(mode=int(_enum(DisplacementMode, mode)), exact_normals=1 if exact_normals else 0,
                                   threads=int(threads), sharp_angle_degrees=float(sharp_angle_degrees))
    return Binding._make(cage._context, _lib.lib.cagekit_multires_bind, cage._handle, scan._handle,
                         ctypes.byref(options))


class CpuDeformer(Handle):
    """Deforms a bound scan on the CPU. One thread at a time per deformer; it keeps its output
    arrays between calls so that update() recomputes only the moved points' support."""

    _release_name = "cagekit_cpu_deformer_release"
    _kind = "deformer"

    def __init__(self, binding: Binding, threads: int = 0) -> None:
        out = ctypes.c_void_p()
        binding._context._call(_lib.lib.cagekit_cpu_deformer_create, binding._handle, int(threads),
                               ctypes.byref(out), outs=[(out, self._release())])
        Handle.__init__(self, out.value, binding._context)
        self.binding = binding
        info = binding.info()
        self.vertex_count: int = info.vertex_count
        self.control_count: int = info.control_count
        self.updated_count: int
        self._arrays: Dict[Any, Tuple[np.ndarray, np.ndarray]] = {}  # dtype -> (positions, normals), made on first use
        self._count_out = ctypes.c_uint32()  # the calls' vertex count output, made once (per frame)

    def _buffers(self, dtype):
        dtype = np.dtype(dtype)
        if dtype not in (np.dtype(np.float64), np.dtype(np.float32)):
            raise ValueError("cagekit: dtype must be float64 or float32")
        if dtype not in self._arrays:
            self._arrays[dtype] = (np.zeros((self.vertex_count, 3), dtype), np.zeros((self.vertex_count, 3), dtype))
        return dtype, self._arrays[dtype]

    def _outputs(self, dtype, normals, copy):
        p, n = self._arrays[dtype]
        n = n if normals else None
        if copy:
            return p.copy(), (None if n is None else n.copy())
        p = p.view()
        p.flags.writeable = False
        if n is not None:
            n = n.view()
            n.flags.writeable = False
        return p, n

    def deform(self, control: npt.ArrayLike, normals: bool = True,
               normal_mode: Union[NormalMode, int, str] = NormalMode.APPROXIMATE, copy: bool = True,
               dtype: npt.DTypeLike = "float64") -> Tuple[np.ndarray, Optional[np.ndarray]]:
        """Recomputes every vertex for `control` ((C, 3) moved control points): returns
        (positions (V, 3), unit normals (V, 3) or None when normals=False) as float64, or float32
        with dtype="float32" (the float64 values rounded; less memory traffic, faster). copy=False
        returns read-only views of the deformer's own arrays (valid until its next call)."""
        dtype, (positions, normal_array) = self._buffers(dtype)
        ctrl = _arrays.control(control, self.control_count)
        fn = _lib.lib.cagekit_cpu_deformer_deform_f32 if dtype == np.float32 else _lib.lib.cagekit_cpu_deformer_deform
        self._context._call(fn, self._handle, _lib.address(ctrl), self.control_count, int(_enum(NormalMode, normal_mode)),
                            self.vertex_count, ctypes.byref(self._count_out), _lib.address(positions),
                            _lib.address(normal_array) if normals else None)
        self._had_normals = bool(normals)
        self._dtype = dtype
        return self._outputs(dtype, normals, copy)

    def update(self, control: npt.ArrayLike, moved: npt.ArrayLike, normals: bool = True,
               normal_mode: Union[NormalMode, int, str] = NormalMode.APPROXIMATE,
               copy: bool = True) -> Tuple[np.ndarray, Optional[np.ndarray]]:
        """Incremental: only the control points `moved` changed since the last deform/update
        (with the same normal_mode); only their support is recomputed. Returns
        (positions, normals) as deform, in the dtype of the last deform();
        `updated_count` holds the vertices recomputed."""
        if not hasattr(self, "_had_normals"):
            raise ValueError("cagekit: update() needs a deform() first")
        if normals and not self._had_normals:
            raise ValueError("cagekit: update(normals=True) after a deform without normals")
        dtype, (positions, normal_array) = self._buffers(self._dtype)
        ctrl = _arrays.control(control, self.control_count)
        moved_indices = _arrays.indices(moved, "moved")
        updated = ctypes.c_uint32()
        fn = _lib.lib.cagekit_cpu_deformer_update_f32 if dtype == np.float32 else _lib.lib.cagekit_cpu_deformer_update
        self._context._call(fn, self._handle, _lib.address(ctrl), self.control_count, _lib.address(moved_indices),
                            moved_indices.size,
                            int(_enum(NormalMode, normal_mode)), self.vertex_count, ctypes.byref(self._count_out),
                            _lib.address(positions), _lib.address(normal_array) if normals else None,
                            ctypes.byref(updated))
        self.updated_count = updated.value
        self._had_normals = bool(normals)
        return self._outputs(dtype, normals, copy)
