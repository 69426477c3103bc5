# SPDX-License-Identifier: GPL-3.0-or-later
"""The peer of `cagekit render` for tests/bench/bench_render: Blender's Workbench engine drawing one mesh
from four views (front, side, top, iso) into a 2 x 2 grid of tiles, headless.

    blender -b --factory-startup -noaudio --python tests/bench/render_blender.py -- IN.obj OUT.png SIZE

SIZE is the whole picture's width and height in pixels (each view is SIZE/2 square, as `cagekit render
--views front,side,top,iso --size SIZExSIZE` lays them out). The OBJ import and the four renders are timed
separately (time.perf_counter) and printed as one JSON line: {"import_seconds", "render_seconds",
"triangles"}; the tiles are composed into OUT.png with Blender's image API. Workbench, solid studio
lighting, no anti-aliasing (viewport_aa 'OFF', render_aa 'OFF'), like CageKit's deterministic drawing.
"""
import json
import math
import sys
import time

import bpy
import mathutils

argv = sys.argv[sys.argv.index("--") + 1:]
path, out, size = argv[0], argv[1], int(argv[2])
bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene
t = time.perf_counter()
bpy.ops.import_scene.obj(filepath=path, split_mode='OFF', axis_forward='-Z', axis_up='Y')
import_seconds = time.perf_counter() - t
obj = bpy.context.selected_objects[0]
triangles = sum(len(p.vertices) - 2 for p in obj.data.polygons)

scene.render.engine = 'BLENDER_WORKBENCH'
scene.display.render_aa = 'OFF'
scene.display.shading.light = 'STUDIO'
scene.render.resolution_x = scene.render.resolution_y = size // 2
scene.render.resolution_percentage = 100
scene.render.image_settings.file_format = 'PNG'
scene.render.film_transparent = False
corners = [obj.matrix_world @ mathutils.Vector(c) for c in obj.bound_box]
lo = mathutils.Vector([min(v[i] for v in corners) for i in range(3)])
hi = mathutils.Vector([max(v[i] for v in corners) for i in range(3)])
centre, radius = (lo + hi) / 2, (hi - lo).length / 2
camera = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
scene.collection.objects.link(camera)
scene.camera = camera
camera.data.angle = math.radians(30.0)
distance = radius / math.sin(camera.data.angle / 2) * 1.05
views = {"front": (0, -1, 0), "side": (1, 0, 0), "top": (0, 0, 1), "iso": (1, -1, 1)}
tiles = []
t = time.perf_counter()
for name, direction in views.items():
    d = mathutils.Vector(direction).normalized()
    camera.location = centre + d * distance
    up = mathutils.Vector((0, 1, 0)) if name == "top" else mathutils.Vector((0, 0, 1))
    camera.rotation_euler = (-d).to_track_quat('-Z', 'Y' if name == "top" else 'Z').to_euler()
    scene.render.filepath = out + "." + name + ".png"
    bpy.ops.render.render(write_still=True)
    tiles.append(scene.render.filepath)
render_seconds = time.perf_counter() - t
half = size // 2
grid = bpy.data.images.new("grid", size, size, alpha=True)
pixels = [0.0] * (size * size * 4)
for k, tile_path in enumerate(tiles):
    tile = bpy.data.images.load(tile_path)
    tp = tile.pixels[:]
    ox, oy = (k % 2) * half, (1 - k // 2) * half
    for y in range(half):
        row = (oy + y) * size + ox
        pixels[row * 4:(row + half) * 4] = tp[y * half * 4:(y + 1) * half * 4]
grid.pixels[:] = pixels
grid.filepath_raw = out
grid.file_format = 'PNG'
grid.save()
print(json.dumps({"import_seconds": import_seconds, "render_seconds": render_seconds, "triangles": triangles}))
