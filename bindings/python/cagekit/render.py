# SPDX-License-Identifier: GPL-3.0-or-later
"""Pictures of scans, cages (their limit surfaces), error maps and deformed scans
(cagekit_render_*; the SDK's render module draws headless through EGL, no display needed).

    pic = cagekit.render([scan, cage, (cage, {"error": scan})], size=(960, 400), creases=True)
    pic.shape          # (400, 960, 4) uint8 RGBA, rows top first; Jupyter shows it (_repr_png_)
    with cagekit.render_scene([cage], error=scan) as s:   # the same scene, for reading back
        s.item_info(0).scalar_max, s.scalars(0)        # the two-sided distance per drawn vertex
    cagekit.render_png("overview.png", [scan, cage], views="front,iso")

Items, one column each in the order given (scan | cage over limit | error map | deformed):
  - a Mesh (drawn shaded) or a Cage (drawn as its Catmull-Clark limit surface);
  - (object, {options}) or (kind, object) or (kind, object, {options}), kind one of "mesh",
    "cage", "deformed" (a mesh in the deformed-scan colour); the kind defaults from the type;
  - a dict {"object": obj, "kind": ..., **options}.
Per-item options (each defaults to the render() argument of the same name where there is one):
  title (str), wire (default: render()'s wire for cages, and for meshes when no item is a cage),
  creases (cages), level (cage refinement levels 1..6, 0 automatic),
  error (a Mesh: colour the item by its two-sided distance to it, with a legend), scalars (one
  value per drawn vertex, see RenderScene.item_info(i).vertex_count), colormap ("viridis" or
  "diverging"), range ((min, max); default: the values' own), legend (bool), label (the legend's
  quantity), overlay (draw in the previous item's column), surface (bool), color, wire_color,
  crease_color ((r, g, b) or (r, g, b, a) in [0, 1]).
Views: "front", "side", "top", "iso", a comma-separated string or a list of them, or dicts
{"eye": (x, y, z), "target": ..., "up": ..., "fov": degrees} for custom cameras; one row per
view (one item column: a near-square grid of views). Every tile shares one scale.

Errors raise the SDK's exceptions with its message: UnsupportedFeatureError when no EGL display
or GL 3.3 / GLES 3.0 context can be made (or the library was built without the render module),
InvalidArgumentError for bad options; ValueError for items or views this module cannot read.
RenderScene is the handle itself, for the per-step API (scalars read back, geometry, GL drawing
into a host context through cagekit_gl_render_scene_draw is declared but not wrapped).

The C declarations of this part of the header are made here (STRUCTS, PROTOTYPES, `lib`).
"""
from __future__ import annotations

import ctypes
from typing import TYPE_CHECKING, Any, Mapping, Optional, Sequence, Tuple, Type, Union
from ctypes import POINTER, c_char_p, c_double, c_float, c_size_t, c_uint8, c_uint32, c_void_p

from . import _lib, _typing
from ._formats import blob_bytes, path_bytes
from ._handle import Handle
from ._numpy import np, npt
from ._records import Record, from_struct
from ._typing import StrPath
from .cage import Cage
from .context import Context, resolve
from .mesh import Mesh

if TYPE_CHECKING:
    import cagekit as _package
else:
    _package = _typing.loaded("cagekit")  # cagekit.Picture: _picture_class(), made on first use

# A view: "front", "side", "top", "iso", or a camera {"eye": (x, y, z), "target": ..., "up": ..., "fov": degrees};
# views: one of them, a comma-separated string of names, or a sequence of them (one row each).
View = Union[str, Mapping[str, Any]]
Views = Union[str, Mapping[str, Any], Sequence[View]]
# An item of render(): a Mesh or a Cage, (object, {options}), (kind, object[, {options}]), or a dict
# {"object": obj, "kind": ..., **options}; items: one item or a sequence of them.
Item = Union[Mesh, Cage, Tuple[Any, ...], Mapping[str, Any]]
Items = Union[Item, Sequence[Item]]
Color = Optional[Sequence[float]]


# --- declarations (include/cagekit/cagekit.h, "Rendering"; cagekit_gl.h) ---------------------
class RenderItemOptions(_lib._Versioned):
    _fields_ = [("struct_size", c_size_t), ("surface", _lib.c_bool32), ("wireframe", _lib.c_bool32),
                ("creases", _lib.c_bool32), ("overlay", _lib.c_bool32), ("tessellation_level", c_uint32),
                ("color", c_float * 4), ("wire_color", c_float * 4), ("crease_color", c_float * 4),
                ("title", c_char_p)]
    _defaults = {"surface": 1}


class RenderScalarOptions(_lib._Versioned):
    _fields_ = [("struct_size", c_size_t), ("colormap", _lib.c_enum), ("auto_range", _lib.c_bool32),
                ("range_min", c_double), ("range_max", c_double), ("legend", _lib.c_bool32), ("label", c_char_p)]
    _defaults = {"colormap": 0, "auto_range": 1, "legend": 1}


class RenderCamera(_lib._Versioned):
    _fields_ = [("struct_size", c_size_t), ("view", _lib.c_enum), ("eye", c_double * 3), ("target", c_double * 3),
                ("up", c_double * 3), ("fov_degrees", c_double)]
    _defaults = {"view": 3, "eye": (0.0, 0.0, 1.0), "up": (0.0, 1.0, 0.0), "fov_degrees": 30.0}


class RenderOptions(_lib._Versioned):
    _fields_ = [("struct_size", c_size_t), ("width", c_uint32), ("height", c_uint32), ("background", c_float * 4),
                ("labels", _lib.c_bool32), ("display", _lib.c_enum), ("egl_library", c_char_p)]
    _defaults = {"width": 800, "height": 600, "background": (1.0, 1.0, 1.0, 1.0), "labels": 1, "display": 0}


class RenderItemInfo(_lib._Versioned):
    _fields_ = [("struct_size", c_size_t), ("kind", _lib.c_enum), ("column", c_uint32), ("vertex_count", c_uint32),
                ("triangle_count", c_uint32), ("tessellation_level", c_uint32), ("has_scalars", _lib.c_bool32),
                ("scalar_min", c_double), ("scalar_max", c_double), ("bounds_min", c_double * 3),
                ("bounds_max", c_double * 3)]


STRUCTS = {"cagekit_render_item_options": RenderItemOptions, "cagekit_render_scalar_options": RenderScalarOptions,
           "cagekit_render_camera": RenderCamera, "cagekit_render_options": RenderOptions,
           "cagekit_render_item_info": RenderItemInfo}
_S, _h, _pp, _u32p = _lib.c_status, c_void_p, POINTER(c_void_p), POINTER(c_uint32)
PROTOTYPES = {
    "cagekit_render_scene_create": (_S, [_h, _pp]),
    "cagekit_render_scene_retain": (None, [_h]),
    "cagekit_render_scene_release": (None, [_h]),
    "cagekit_render_scene_set_options": (_S, [_h, POINTER(RenderOptions)]),
    "cagekit_render_scene_get_options": (_S, [_h, POINTER(RenderOptions)]),
    "cagekit_render_scene_set_views": (_S, [_h, c_uint32, POINTER(RenderCamera)]),
    "cagekit_render_scene_add_mesh": (_S, [_h, _h, _lib.c_enum, POINTER(RenderItemOptions), _u32p]),
    "cagekit_render_scene_add_cage": (_S, [_h, _h, POINTER(RenderItemOptions), _u32p]),
    "cagekit_render_scene_set_scalars": (_S, [_h, c_uint32, c_uint32, c_void_p, POINTER(RenderScalarOptions)]),
    "cagekit_render_scene_set_distance_to_scan": (_S, [_h, c_uint32, _h, POINTER(RenderScalarOptions)]),
    "cagekit_render_scene_get_scalars": (_S, [_h, c_uint32, c_uint32, _u32p, c_void_p]),
    "cagekit_render_scene_get_item_geometry": (_S, [_h, c_uint32, c_uint32, _u32p, c_void_p, c_uint32, _u32p,
                                                    c_void_p]),
    "cagekit_render_scene_get_item_count": (_S, [_h, _u32p]),
    "cagekit_render_scene_get_item_info": (_S, [_h, c_uint32, POINTER(RenderItemInfo)]),
    "cagekit_render_scene_draw": (_S, [_h, c_uint32, _u32p, c_void_p]),
    "cagekit_render_scene_write_png": (_S, [_h, c_char_p]),
    "cagekit_render_scene_encode_png": (_S, [_h, _pp]),
    "cagekit_render_encode_png": (_S, [_h, c_void_p, c_uint32, c_uint32, c_char_p, _pp]),
    "cagekit_gl_render_scene_draw": (_S, [_h, _lib.GL_GET_PROC_ADDRESS_FN, c_void_p, c_uint32, _u32p,
                                          POINTER(c_uint8)]),
}
lib = _lib.Functions(PROTOTYPES)  # ImportError naming the function when the loaded library lacks one

_OPTIONS = RenderOptions.defaults()  # CAGEKIT_RENDER_OPTIONS_INIT, written once (in RenderOptions)
VIEWS = {"front": 0, "side": 1, "top": 2, "iso": 3}
KINDS = {"mesh": 0, "cage": 1, "deformed": 2}
COLORMAPS = {"viridis": 0, "diverging": 1}
_ITEM_KEYS = {"object", "kind", "title", "wire", "creases", "level", "error", "scalars", "colormap", "range",
              "legend", "label", "overlay", "surface", "color", "wire_color", "crease_color"}


def encode_png(rgba: npt.ArrayLike, context: Optional[Context] = None) -> bytes:
    """PNG bytes of an (H, W, 4) uint8 RGBA array (rows top first), by the SDK's libpng writer."""
    a = np.ascontiguousarray(np.asarray(rgba, dtype=np.uint8))
    if a.ndim != 3 or a.shape[2] != 4:
        raise ValueError("cagekit: an RGBA image must have shape (H, W, 4), not %s" % (a.shape,))
    ctx = resolve(context)
    blob = ctypes.c_void_p()
    ctx._call(lib.cagekit_render_encode_png, ctx._handle, _lib.address(a), a.shape[1], a.shape[0], None,
              ctypes.byref(blob), outs=[(blob, "cagekit_blob_release")])
    return blob_bytes(blob)


def _picture_class():  # -> Type[Picture]
    """Picture: a numpy.ndarray subclass (made when numpy is first needed)."""
    global Picture
    if Picture is not None:
        return Picture

    class _Picture(np.ndarray):
        """An (H, W, 4) uint8 RGBA image, rows top first: a numpy array that Jupyter / IPython
        shows as a picture (_repr_png_). png() gives the PNG bytes, save(path) writes them."""

        def _repr_png_(self) -> Optional[bytes]:
            if self.ndim != 3 or self.shape[2] != 4 or self.dtype != np.uint8 or 0 in self.shape:
                return None  # a slice that is no RGBA image any more: shown as an array
            return encode_png(np.asarray(self))

        def png(self) -> bytes:
            """The PNG bytes of the picture (8-bit RGBA)."""
            data = self._repr_png_()
            if data is None:
                raise ValueError("cagekit: not an (H, W, 4) uint8 picture: shape %s, %s" % (self.shape, self.dtype))
            return data

        def save(self, path: StrPath) -> None:
            """Writes the picture as a PNG file."""
            with open(path, "wb") as f:
                f.write(self.png())

    _Picture.__name__ = _Picture.__qualname__ = "Picture"
    _Picture.__module__ = __name__
    Picture = _Picture
    return Picture


if TYPE_CHECKING:
    class Picture(np.ndarray):
        """What type checkers see of the class _picture_class() makes."""

        def _repr_png_(self) -> Optional[bytes]: ...

        def png(self) -> bytes: ...

        def save(self, path: StrPath) -> None: ...
else:
    Picture = None  # the class, made on first use (numpy is imported lazily); see _picture_class


def _color(value, name):
    if value is None:
        return (0.0, 0.0, 0.0, 0.0)  # alpha 0: the SDK's default colour
    c = [float(v) for v in value]
    if len(c) == 3:
        c.append(1.0)
    if len(c) != 4:
        raise ValueError("cagekit: %s must be (r, g, b) or (r, g, b, a) in [0, 1], not %r" % (name, value))
    return tuple(c)


def _cameras(views):
    if isinstance(views, str):
        views = [v.strip() for v in views.split(",")]
    elif isinstance(views, dict):
        views = [views]
    cameras = []
    for v in views:
        if isinstance(v, str):
            if v not in VIEWS:
                raise ValueError("cagekit: unknown view %r (front, side, top, iso, or a dict with eye, target, up)"
                                 % v)
            cameras.append(RenderCamera.new(view=VIEWS[v]))
        elif isinstance(v, dict):
            unknown = set(v) - {"eye", "target", "up", "fov"}
            if unknown:
                raise ValueError("cagekit: unknown camera keys %s (eye, target, up, fov)" % sorted(unknown))
            camera = RenderCamera.new(view=4)
            for key, field in (("eye", "eye"), ("target", "target"), ("up", "up")):
                if key in v:
                    setattr(camera, field, tuple(float(x) for x in v[key]))
            if "fov" in v:
                camera.fov_degrees = float(v["fov"])
            cameras.append(camera)
        else:
            raise ValueError("cagekit: a view is a name or a dict, not %r" % (v,))
    if not cameras:
        raise ValueError("cagekit: no views")
    return cameras


def _item(entry):
    """(kind name, object, options dict) of one item of render()."""
    if isinstance(entry, (Mesh, Cage)):
        obj, kind, options = entry, None, {}
    elif isinstance(entry, dict):
        options = dict(entry)
        obj, kind = options.pop("object", None), options.pop("kind", None)
    elif isinstance(entry, (tuple, list)):
        parts = list(entry)
        kind = parts.pop(0) if parts and isinstance(parts[0], str) else None
        obj = parts.pop(0) if parts else None
        options = dict(parts.pop(0)) if parts and isinstance(parts[0], dict) else {}
        if parts:
            raise ValueError("cagekit: an item tuple is (object, {options}), (kind, object) or (kind, object, {options})")
    else:
        raise ValueError("cagekit: an item is a Mesh, a Cage, a tuple or a dict, not %r" % (entry,))
    if not isinstance(obj, (Mesh, Cage)):
        raise ValueError("cagekit: an item's object must be a cagekit Mesh or Cage, not %r" % (obj,))
    if kind is None:
        kind = "cage" if isinstance(obj, Cage) else "mesh"
    if kind not in KINDS:
        raise ValueError("cagekit: unknown item kind %r (mesh, cage, deformed)" % (kind,))
    if (kind == "cage") != isinstance(obj, Cage):
        raise ValueError("cagekit: a %s item needs a %s" % (kind, "Cage" if kind == "cage" else "Mesh"))
    unknown = set(options) - _ITEM_KEYS
    if unknown:
        raise ValueError("cagekit: unknown item options %s (%s)" % (sorted(unknown), ", ".join(sorted(_ITEM_KEYS - {"object", "kind"}))))
    return kind, obj, options


class RenderScene(Handle):
    """A scene of items drawn into one RGBA image (cagekit_render_scene; see the module doc)."""

    _release_name = "cagekit_render_scene_release"
    _functions = lib
    _kind = "render scene"

    def __init__(self, size: Tuple[int, int] = (_OPTIONS["width"], _OPTIONS["height"]), views: Views = "iso",
                 labels: bool = bool(_OPTIONS["labels"]), background: Sequence[float] = tuple(_OPTIONS["background"]),
                 egl_library: Optional[StrPath] = None, context: Optional[Context] = None) -> None:
        ctx = resolve(context)
        out = ctypes.c_void_p()
        ctx._call(lib.cagekit_render_scene_create, ctx._handle, ctypes.byref(out),
                  outs=[(out, self._release())])
        Handle.__init__(self, out.value, ctx)
        self.set_options(size=size, labels=labels, background=background, egl_library=egl_library)
        self.set_views(views)

    def set_options(self, size: Tuple[int, int] = (_OPTIONS["width"], _OPTIONS["height"]),
                    labels: bool = bool(_OPTIONS["labels"]),
                    background: Sequence[float] = tuple(_OPTIONS["background"]),
                    egl_library: Optional[StrPath] = None) -> None:
        """size (W, H) in pixels (1..16384 each), labels (titles, view names, legends), background
        (r, g, b[, a]) in [0, 1], egl_library (the libEGL to load; None: $CAGEKIT_EGL_LIBRARY or
        libEGL.so.1)."""
        width, height = (int(v) for v in size)
        options = RenderOptions.new(width=width, height=height, labels=1 if labels else 0,
                                    background=_color(background, "background"),
                                    egl_library=None if egl_library is None else path_bytes(egl_library))
        self._context._call(lib.cagekit_render_scene_set_options, self._handle, ctypes.byref(options))
        self._size = (width, height)

    @property
    def size(self) -> Tuple[int, int]:
        """(width, height) of the image."""
        return self._size

    def set_views(self, views: Views) -> None:
        """One camera per row (see the module doc)."""
        cameras = _cameras(views)
        array = (RenderCamera * len(cameras))(*cameras)
        self._context._call(lib.cagekit_render_scene_set_views, self._handle, len(cameras), array)

    def add(self, kind: str, obj: Union[Mesh, Cage], title: Optional[str] = None, wire: bool = False,
            creases: bool = False, level: int = 0, overlay: bool = False, surface: bool = True, color: Color = None,
            wire_color: Color = None, crease_color: Color = None) -> int:
        """Adds a "mesh", "cage" or "deformed" item; returns its index."""
        title_bytes = None if title is None else str(title).encode("utf-8")
        options = RenderItemOptions.new(surface=1 if surface else 0, wireframe=1 if wire else 0,
                                        creases=1 if creases else 0, overlay=1 if overlay else 0,
                                        tessellation_level=int(level), color=_color(color, "color"),
                                        wire_color=_color(wire_color, "wire_color"),
                                        crease_color=_color(crease_color, "crease_color"), title=title_bytes)
        index = c_uint32()
        if kind == "cage":
            self._context._call(lib.cagekit_render_scene_add_cage, self._handle, obj._handle, ctypes.byref(options),
                                ctypes.byref(index))
        else:
            self._context._call(lib.cagekit_render_scene_add_mesh, self._handle, obj._handle, KINDS[kind],
                                ctypes.byref(options), ctypes.byref(index))
        return index.value

    @staticmethod
    def _scalar_options(colormap, range, legend, label):
        if colormap not in COLORMAPS:
            raise ValueError("cagekit: unknown colormap %r (viridis, diverging)" % (colormap,))
        lo, hi = (0.0, 0.0) if range is None else (float(range[0]), float(range[1]))
        return RenderScalarOptions.new(colormap=COLORMAPS[colormap], auto_range=1 if range is None else 0,
                                       range_min=lo, range_max=hi, legend=1 if legend else 0,
                                       label=None if label is None else str(label).encode("utf-8"))

    def set_scalars(self, item: int, values: npt.ArrayLike, colormap: str = "viridis",
                    range: Optional[Tuple[float, float]] = None, legend: bool = True,
                    label: Optional[str] = None) -> None:
        """Colours item `item` by one value per drawn vertex."""
        v = np.ascontiguousarray(np.asarray(values, dtype=np.float64).reshape(-1))
        options = self._scalar_options(colormap, range, legend, label)
        self._context._call(lib.cagekit_render_scene_set_scalars, self._handle, int(item), v.size, _lib.address(v),
                            ctypes.byref(options))

    def set_distance_to_scan(self, item: int, scan: Mesh, colormap: str = "viridis",
                             range: Optional[Tuple[float, float]] = None, legend: bool = True,
                             label: Optional[str] = None) -> None:
        """Colours item `item` by its two-sided distance to the Mesh `scan` (absolute units)."""
        options = self._scalar_options(colormap, range, legend, label)
        self._context._call(lib.cagekit_render_scene_set_distance_to_scan, self._handle, int(item), scan._handle,
                            ctypes.byref(options))

    def scalars(self, item: int) -> np.ndarray:
        """(vertex_count,) float64: the item's scalars (empty without)."""
        count = c_uint32()
        self._context._call(lib.cagekit_render_scene_get_scalars, self._handle, int(item), 0, ctypes.byref(count), None)
        out = np.zeros(count.value, dtype=np.float64)
        if count.value:
            self._context._call(lib.cagekit_render_scene_get_scalars, self._handle, int(item), count.value,
                                ctypes.byref(count), _lib.address(out))
        return out

    def geometry(self, item: int) -> Tuple[np.ndarray, np.ndarray]:
        """((V, 3) float64 positions, (T, 3) uint32 triangles) of the surface the item draws."""
        nv, nt = c_uint32(), c_uint32()
        self._context._call(lib.cagekit_render_scene_get_item_geometry, self._handle, int(item), 0, ctypes.byref(nv),
                            None, 0, ctypes.byref(nt), None)
        positions = np.zeros((nv.value, 3), dtype=np.float64)
        triangles = np.zeros((nt.value, 3), dtype=np.uint32)
        self._context._call(lib.cagekit_render_scene_get_item_geometry, self._handle, int(item), nv.value,
                            ctypes.byref(nv), _lib.address(positions), nt.value, ctypes.byref(nt),
                            _lib.address(triangles))
        return positions, triangles

    def __len__(self) -> int:
        count = c_uint32()
        self._context._call(lib.cagekit_render_scene_get_item_count, self._handle, ctypes.byref(count))
        return count.value

    def item_info(self, item: int) -> Record:
        """Record: kind, column, vertex_count, triangle_count, tessellation_level, has_scalars,
        scalar_min, scalar_max (the range the colour map shows), bounds_min, bounds_max."""
        info = RenderItemInfo.new()
        self._context._call(lib.cagekit_render_scene_get_item_info, self._handle, int(item), ctypes.byref(info))
        return from_struct(info, "RenderItemInfo")

    def draw(self) -> _package.Picture:
        """The picture: an (H, W, 4) uint8 Picture (a numpy array Jupyter shows)."""
        width, height = self._size
        image = np.zeros((height, width, 4), dtype=np.uint8)
        count = c_uint32()
        self._context._call(lib.cagekit_render_scene_draw, self._handle, width * height, ctypes.byref(count),
                            _lib.address(image))
        return image.view(_picture_class())

    def write_png(self, path: StrPath) -> None:
        """Draws and writes a PNG file."""
        self._context._call(lib.cagekit_render_scene_write_png, self._handle, path_bytes(path))

    def encode_png(self) -> bytes:
        """Draws and returns the PNG bytes."""
        blob = ctypes.c_void_p()
        self._context._call(lib.cagekit_render_scene_encode_png, self._handle, ctypes.byref(blob),
                            outs=[(blob, "cagekit_blob_release")])
        return blob_bytes(blob)


def render_scene(items: Items, size: Tuple[int, int] = (_OPTIONS["width"], _OPTIONS["height"]), views: Views = "iso",
                 wire: bool = False, creases: bool = False, level: int = 0, error: Optional[Mesh] = None,
                 colormap: str = "viridis", labels: bool = bool(_OPTIONS["labels"]),
                 background: Sequence[float] = tuple(_OPTIONS["background"]), egl_library: Optional[StrPath] = None,
                 context: Optional[Context] = None) -> RenderScene:
    """The RenderScene render() draws, with the same arguments, for reading back what it would
    show (item_info, scalars, geometry) or drawing it more than once. Close it (or use `with`)."""
    # One item given alone: an object, a dict, or a tuple (kind, ...) / (object, {options}).
    if isinstance(items, (Mesh, Cage, dict)) or (isinstance(items, tuple) and items and (
            isinstance(items[0], str) or (len(items) == 2 and isinstance(items[1], dict)))):
        items = [items]
    parsed = [_item(entry) for entry in items]
    if not parsed:
        raise ValueError("cagekit: nothing to render (no items)")
    s = RenderScene(size=size, views=views, labels=labels, background=background, egl_library=egl_library,
                    context=context)
    any_cage = any(kind == "cage" for kind, _, _ in parsed)
    try:
        for kind, obj, o in parsed:
            # A dense scan's edges hide its surface: with cages in the picture, wire= is theirs.
            default_wire = bool(wire) and (kind == "cage" or not any_cage)
            index = s.add(kind, obj, title=o.get("title"), wire=o.get("wire", default_wire),
                          creases=o.get("creases", creases and kind == "cage"), level=o.get("level", level),
                          overlay=o.get("overlay", False), surface=o.get("surface", True), color=o.get("color"),
                          wire_color=o.get("wire_color"), crease_color=o.get("crease_color"))
            scan = o.get("error", error if kind == "cage" else None)
            style = dict(colormap=o.get("colormap", colormap), range=o.get("range"), legend=o.get("legend", True),
                         label=o.get("label"))
            if o.get("scalars") is not None:
                s.set_scalars(index, o["scalars"], **style)
            elif scan is not None:
                if not isinstance(scan, Mesh):
                    raise ValueError("cagekit: error= must be a cagekit Mesh (the scan), not %r" % (scan,))
                s.set_distance_to_scan(index, scan, **style)
    except BaseException:
        s.close()
        raise
    return s


def render(items: Items, size: Tuple[int, int] = (_OPTIONS["width"], _OPTIONS["height"]), views: Views = "iso",
           wire: bool = False, creases: bool = False, level: int = 0, error: Optional[Mesh] = None,
           colormap: str = "viridis", labels: bool = bool(_OPTIONS["labels"]),
           background: Sequence[float] = tuple(_OPTIONS["background"]), egl_library: Optional[StrPath] = None,
           context: Optional[Context] = None) -> _package.Picture:
    """Draws `items` side by side (see the module doc) and returns the picture: an (H, W, 4) uint8
    numpy array (rows top first) of class Picture, which Jupyter shows (_repr_png_).

    size (W, H); views: names or cameras, one row each; wire: the cages' control edges (without
    cages among the items: the meshes' edges); creases: the cages' crease edges (magenta-red); level: the cages' refinement
    levels (0 automatic); error: a scan Mesh, each cage coloured by its two-sided distance to it
    with a legend; colormap "viridis" or "diverging"; labels: titles, view names and legends.
    Per-item options override these. UnsupportedFeatureError when no headless GL can be made."""
    with render_scene(items, size=size, views=views, wire=wire, creases=creases, level=level, error=error,
               colormap=colormap, labels=labels, background=background, egl_library=egl_library,
               context=context) as s:
        return s.draw()


def render_png(path: StrPath, items: Items, size: Tuple[int, int] = (_OPTIONS["width"], _OPTIONS["height"]),
               views: Views = "iso", wire: bool = False, creases: bool = False, level: int = 0,
               error: Optional[Mesh] = None, colormap: str = "viridis", labels: bool = bool(_OPTIONS["labels"]),
               background: Sequence[float] = tuple(_OPTIONS["background"]), egl_library: Optional[StrPath] = None,
               context: Optional[Context] = None) -> _package.Picture:
    """render() written to `path` as a PNG; returns the picture too."""
    picture = render(items, size=size, views=views, wire=wire, creases=creases, level=level, error=error,
                     colormap=colormap, labels=labels, background=background, egl_library=egl_library,
                     context=context)
    with open(path, "wb") as f:
        f.write(picture.png())
    return picture
