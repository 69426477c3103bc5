# SPDX-License-Identifier: GPL-3.0-or-later
"""Structure-preserving simplification (thesis ch. 3): the face-merge hierarchy and the
quad-dominant cage built from one of its levels.

    with cagekit.Hierarchy(scan) as h:              # long: progress, cancel
        h.level = h.find_level(faces=300)
        cage, report = h.build_cage()               # creases where the scan is sharp

or in one call: cage, report = cagekit.simplify(scan, faces=300).
"""
from __future__ import annotations

import ctypes
import enum
from typing import Any, List, Optional, Tuple

from . import _lib
from ._handle import Handle
from ._numpy import np, npt
from ._records import Record, from_struct
from .cage import Cage
from .mesh import Mesh


# CAGEKIT_SIMPLIFY_OPTIONS_INIT and CAGEKIT_CAGE_OPTIONS_INIT, written once (in _lib).
_SIMPLIFY = _lib.SimplifyOptions.defaults()
_CAGE = _lib.CageOptions.defaults()


class LevelQuery(enum.IntEnum):
    BY_FACES = 0
    BY_VERTICES = 1
    BY_ERROR = 2


class Hierarchy(Handle):
    """Every level from the input (0) to the coarsest; starts at the coarsest. Changing the
    level modifies it (one thread at a time)."""

    _release_name = "cagekit_hierarchy_release"
    _kind = "hierarchy"

    def __init__(self, mesh: Mesh, tie_break_epsilon: float = _SIMPLIFY["tie_break_epsilon"],
                 sharp_edges: Optional[npt.ArrayLike] = None) -> None:
        """Simplifies `mesh` (valid apart from unreferenced vertices, else InvalidMeshError) to
        its coarsest level. `sharp_edges`: the host's sharp edges (vertex pairs of `mesh`), borders
        of every level and creases of every cage built from it. Long operation (progress, cancel)
        with the mesh's context."""
        options = _lib.SimplifyOptions.new(tie_break_epsilon=float(tie_break_epsilon))
        keep_alive = _lib.set_sharp_edges(options, sharp_edges)
        out = ctypes.c_void_p()
        mesh._context._call(_lib.lib.cagekit_hierarchy_create, mesh._handle, ctypes.byref(options),
                            ctypes.byref(out), outs=[(out, self._release())])
        del keep_alive
        Handle.__init__(self, out.value, mesh._context)

    @property
    def level_count(self) -> int:
        count = ctypes.c_uint32()
        self._context._call(_lib.lib.cagekit_hierarchy_get_level_count, self._handle, ctypes.byref(count))
        return count.value

    def __len__(self) -> int:
        return self.level_count

    def level_info(self, level: int) -> Record:
        """Record (faces, vertices, error) of any level without moving there."""
        info = _lib.LevelInfo.new()
        self._context._call(_lib.lib.cagekit_hierarchy_get_level_info, self._handle, int(level),
                            ctypes.byref(info))
        return from_struct(info, "LevelInfo")

    def find_level(self, faces: Optional[float] = None, vertices: Optional[float] = None,
                   error: Optional[float] = None) -> int:
        """The finest level with at most `faces` faces or `vertices` vertices, or the coarsest
        whose error is <= `error` (exactly one of them); the coarsest level if none has so few."""
        given = [(q, v) for q, v in ((LevelQuery.BY_FACES, faces), (LevelQuery.BY_VERTICES, vertices),
                                     (LevelQuery.BY_ERROR, error)) if v is not None]
        if len(given) != 1:
            raise ValueError("cagekit: find_level needs exactly one of faces=, vertices=, error=")
        level = ctypes.c_uint32()
        self._context._call(_lib.lib.cagekit_hierarchy_find_level, self._handle, int(given[0][0]),
                            float(given[0][1]), ctypes.byref(level))
        return level.value

    @property
    def level(self) -> int:
        level = ctypes.c_uint32()
        self._context._call(_lib.lib.cagekit_hierarchy_get_current_level, self._handle, ctypes.byref(level))
        return level.value

    @level.setter
    def level(self, level: int) -> None:
        self._context._call(_lib.lib.cagekit_hierarchy_set_level, self._handle, int(level))

    def set_level(self, level: Optional[int] = None, *, faces: Optional[float] = None,
                  vertices: Optional[float] = None, error: Optional[float] = None) -> int:
        """Moves to `level`, or to find_level(faces=|vertices=|error=); returns the level."""
        if level is None:
            level = self.find_level(faces=faces, vertices=vertices, error=error)
        self.level = level
        return level

    def current_info(self) -> Record:
        """Record of the current level: level, faces, vertices, faces_with_holes, invalid_faces,
        l2_error, l21_error."""
        info = _lib.PolygonalLevelInfo.new()
        self._context._call(_lib.lib.cagekit_hierarchy_get_current_info, self._handle, ctypes.byref(info))
        return from_struct(info, "PolygonalLevelInfo")

    def face_arrays(self) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(loops_per_face, loop_sizes, loop_vertices) uint32 arrays of the current level; the
        first loop of a face is its outer loop, the others holes; vertices are input indices."""
        fn = _lib.lib.cagekit_hierarchy_get_faces
        faces, loops, indices = ctypes.c_uint32(), ctypes.c_uint32(), ctypes.c_uint64()
        self._context._call(fn, self._handle, 0, ctypes.byref(faces), None, 0, ctypes.byref(loops), None, 0,
                            ctypes.byref(indices), None)
        per_face = np.empty(faces.value, dtype=np.uint32)
        sizes = np.empty(loops.value, dtype=np.uint32)
        verts = np.empty(indices.value, dtype=np.uint32)
        self._context._call(fn, self._handle, faces.value, ctypes.byref(faces), _lib.address(per_face),
                            loops.value, ctypes.byref(loops), _lib.address(sizes), indices.value,
                            ctypes.byref(indices), _lib.address(verts))
        return per_face, sizes, verts

    def faces(self) -> List[List[np.ndarray]]:
        """The current level's faces: for each face a list of loops (uint32 arrays of input
        vertex indices), outer loop first."""
        per_face, sizes, verts = self.face_arrays()
        loops = np.split(verts, np.cumsum(sizes[:-1].astype(np.int64))) if len(sizes) else []
        out, at = [], 0
        for n in per_face:
            out.append(loops[at:at + int(n)])
            at += int(n)
        return out

    def clusters(self) -> np.ndarray:
        """For each input face, the index of the current level's face that contains it."""
        fn, count = _lib.lib.cagekit_hierarchy_get_clusters, ctypes.c_uint32()
        self._context._call(fn, self._handle, 0, ctypes.byref(count), None)
        out = np.empty(count.value, dtype=np.uint32)
        self._context._call(fn, self._handle, count.value, ctypes.byref(count), _lib.address(out))
        return out

    def polygon_mesh(self) -> Mesh:
        """The current level as a Mesh over the input vertices it uses (renumbered); faces with
        holes are split into constrained Delaunay triangles."""
        return Mesh._make(self._context, _lib.lib.cagekit_hierarchy_get_polygon_mesh, self._handle)

    def refined_polygon_mesh(self, chord_tolerance: float) -> Mesh:
        """polygon_mesh() with border vertices put back where a cluster border strays farther than
        chord_tolerance x the input's bbox diagonal from its level edge (same faces, more
        vertices, closer to the input at coarse levels)."""
        return Mesh._make(self._context, _lib.lib.cagekit_hierarchy_get_refined_polygon_mesh, self._handle,
                          float(chord_tolerance))

    def build_cage(self, crease_rule: str = _lib.crease_rule_name(_CAGE["crease_rule"]),
                   feature_angle_degrees: float = _CAGE["feature_angle_degrees"],
                   crease_angle_degrees: float = _CAGE["crease_angle_degrees"],
                   tag_boundary_edges: bool = bool(_CAGE["tag_boundary_edges"]),
                   exact_partition_limit: int = _CAGE["exact_partition_limit"],
                   input_crease_angle_degrees: float = _CAGE["input_crease_angle_degrees"],
                   sharp_edges: Optional[npt.ArrayLike] = None) -> Tuple[Cage, Record]:
        """The quad-dominant control cage of the current level with crease tags, and its report
        (quads, triangles, pentagons, other_polygons, creases, ...). crease_rule "sharp-input"
        (default): creases where the scan is sharp (input edges above feature_angle_degrees,
        noise filtered); "cluster-angle": the thesis's rule, clusters whose normals differ by more
        than crease_angle_degrees (and, with input_crease_angle_degrees >= 0, an input that is
        that sharp on average along their border). `sharp_edges`: more host sharp edges (vertex
        pairs of the input), creases like those the hierarchy was made with (sharp-input rule)."""
        options = _lib.CageOptions.new(crease_rule=_lib.crease_rule_value(crease_rule),
                                       feature_angle_degrees=float(feature_angle_degrees),
                                       crease_angle_degrees=float(crease_angle_degrees),
                                       tag_boundary_edges=1 if tag_boundary_edges else 0,
                                       exact_partition_limit=int(exact_partition_limit),
                                       input_crease_angle_degrees=float(input_crease_angle_degrees))
        keep_alive = _lib.set_sharp_edges(options, sharp_edges)
        report = _lib.CageReport.new()
        out = ctypes.c_void_p()
        self._context._call(_lib.lib.cagekit_hierarchy_build_cage, self._handle, ctypes.byref(options),
                            ctypes.byref(out), ctypes.byref(report), outs=[(out, Cage._release())])
        return Cage._wrap(out.value, self._context), from_struct(report, "CageReport")


def simplify(mesh: Mesh, faces: Optional[float] = None, vertices: Optional[float] = None,
             tie_break_epsilon: float = _SIMPLIFY["tie_break_epsilon"], sharp_edges: Optional[npt.ArrayLike] = None,
             **cage_options: Any) -> Tuple[Cage, Record]:
    """Simplifies `mesh` to at most `faces` faces or `vertices` vertices and builds the
    quad-dominant cage: (Cage, CageReport). `sharp_edges` as Hierarchy(); cage_options as
    Hierarchy.build_cage."""
    with Hierarchy(mesh, tie_break_epsilon, sharp_edges) as hierarchy:
        hierarchy.set_level(faces=faces, vertices=vertices)
        return hierarchy.build_cage(**cage_options)
