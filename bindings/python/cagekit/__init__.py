# SPDX-License-Identifier: GPL-3.0-or-later
"""cagekit: Python bindings of the CageKit SDK over its C ABI (ctypes; no compiled extension).

Structure-preserving Catmull-Clark models from dense triangle meshes: simplification to a
quad-dominant cage with creases, fitting of its limit surface to the scan, and multiresolution
editing of the scan through the cage.

    import numpy as np, cagekit
    scan = cagekit.Mesh.read("scan.obj")
    cage, _ = cagekit.simplify(scan, faces=300)
    fitted, report = cagekit.fit(cage, scan)
    binding = cagekit.bind(fitted, scan)
    positions, normals = cagekit.CpuDeformer(binding).deform(binding.control_points())
    cagekit.render([scan, fitted, (fitted, {"error": scan})], size=(960, 400), creases=True)  # a picture

The shared library is found through CAGEKIT_LIBRARY, a copy next to this package, or the
system loader (see cagekit._lib). Every C call releases the GIL; errors raise CageKitError
subclasses carrying the SDK's message; handles are released by close(), `with` or collection.
numpy is needed for arrays only: `import cagekit` works without it.
"""
from __future__ import annotations

import sys as _sys
from typing import TYPE_CHECKING as _TYPE_CHECKING, Any as _Any

from . import _lib
from ._errors import (CageKitError, CancelledError, FileIOError, InternalError, InvalidArgumentError,
                      InvalidHandleError, InvalidMeshError, LimitExceededError, OutOfMemoryError, ParseError,
                      SizeInsufficientError, UnsupportedFormatError, VersionMismatchError, QualityError,
                      UnsupportedFeatureError, InvalidOperationError)
from ._formats import FileFormat
from ._handle import live_handles
from ._records import Record
from .cage import SHARP, BoundaryRule, Cage
from .context import Context, LogLevel, default_context
from .fit import LsqSolver, ProjectionMode, fit
from .limit_patches import LimitPatches, limit_patches
from .limit_surfaces import BorderKind, BSplineSurface, LimitSurfaces, limit_surfaces
from .mesh import Mesh, MeshIssue, RepairSteps
from .multires import Binding, CpuDeformer, DisplacementMode, NormalMode, bind
from .remesh import remesh_anisotropic, remesh_quad
from .render import RenderScene, render, render_png, render_scene
from .scan_to_cage import ComponentMode, ScanMethod, scan_to_cage
from .simplify import Hierarchy, LevelQuery, simplify
from .surface import Surface

if _TYPE_CHECKING:
    from .render import Picture  # at run time made on first use: see __getattr__

ABI_VERSION = _lib.ABI_VERSION
MAX_SUBDIVISION_LEVELS = _lib.MAX_SUBDIVISION_LEVELS
__version__ = "0.2.0"
library_path = _lib.path


def __getattr__(name: str) -> _Any:
    """cagekit.Picture: the class of render()'s arrays (a numpy.ndarray subclass, made when numpy is
    first imported)."""
    if name == "Picture":
        return _sys.modules[__name__ + ".render"]._picture_class()
    raise AttributeError("module 'cagekit' has no attribute %r" % name)


def version() -> str:
    """'MAJOR.MINOR.PATCH' of the loaded libcagekit."""
    return _lib.lib.cagekit_version_string().decode()


def abi_version() -> int:
    """ABI major version of the loaded libcagekit (== ABI_VERSION, checked at import)."""
    return _lib.lib.cagekit_abi_version()


__all__ = [
    "ABI_VERSION", "MAX_SUBDIVISION_LEVELS", "SHARP", "Binding", "BoundaryRule", "Cage", "CageKitError",
    "CancelledError", "ComponentMode", "Context", "CpuDeformer", "DisplacementMode", "FileFormat", "FileIOError", "Hierarchy",
    "InternalError", "InvalidArgumentError", "InvalidHandleError", "InvalidMeshError", "LevelQuery",
    "BorderKind", "BSplineSurface", "LimitExceededError", "LimitPatches", "LimitSurfaces", "LogLevel", "LsqSolver", "Mesh", "MeshIssue", "NormalMode",
    "OutOfMemoryError", "ParseError", "ProjectionMode", "Record", "RepairSteps", "ScanMethod", "SizeInsufficientError", "Surface",
    "UnsupportedFormatError", "VersionMismatchError", "QualityError", "UnsupportedFeatureError",
    "InvalidOperationError", "RenderScene", "abi_version", "bind", "default_context", "fit",
    "library_path", "limit_patches", "limit_surfaces", "live_handles", "remesh_anisotropic", "remesh_quad", "render", "render_png", "render_scene",
    "scan_to_cage", "simplify", "version",
]
