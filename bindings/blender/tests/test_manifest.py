# SPDX-License-Identifier: GPL-3.0-or-later
"""Checks blender_manifest.toml (the Blender 4.2+ extension manifest) against the rules of
Blender's extension docs ("How to Create Extensions", manifest reference), since no Blender 4.2+
is installable on Debian 12 to load it: required keys, value formats, the tag and platform
vocabularies used, and agreement with bl_info (Blender 3.x) and the project version.

Run: python3 test_manifest.py PROJECT_VERSION (ctest blender.manifest). With CAGEKIT_ADDON_ZIP=<zip>
(ctest packaging.blender_zip.manifest) the manifest inside the zip made by blender_addon_zip is
checked too: its [build] paths list every file of the zip, the bundled native libraries included."""
import ast
import os
import re
import sys
import tomllib
import unittest
import zipfile

HERE = os.path.dirname(os.path.abspath(__file__))
ADDON = os.path.join(HERE, "..", "cagekit_blender")
PROJECT_VERSION = sys.argv.pop(1) if len(sys.argv) > 1 else None

# From the manifest reference (Blender 4.2).
REQUIRED = ["schema_version", "id", "version", "name", "tagline", "maintainer", "type", "blender_version_min",
            "license"]
ADDON_TAGS = {"3D View", "Add Curve", "Add Mesh", "Animation", "Bake", "Camera", "Compositing", "Development",
              "Game Engine", "Geometry Nodes", "Grease Pencil", "Import-Export", "Lighting", "Material", "Modeling",
              "Mesh", "Node", "Object", "Paint", "Pipeline", "Physics", "Render", "Rigging", "Scene", "Sculpt",
              "Sequencer", "System", "Text Editor", "Tracking", "User Interface", "UV"}
PLATFORMS = {"windows-x64", "windows-arm64", "macos-x64", "macos-arm64", "linux-x64"}
SEMVER = re.compile(r"^\d+\.\d+\.\d+$")


def bl_info():
    tree = ast.parse(open(os.path.join(ADDON, "__init__.py")).read())
    for node in tree.body:
        if isinstance(node, ast.Assign) and any(getattr(t, "id", "") == "bl_info" for t in node.targets):
            return ast.literal_eval(node.value)
    raise AssertionError("no bl_info in __init__.py")


class Manifest(unittest.TestCase):
    def setUp(self):
        with open(os.path.join(ADDON, "blender_manifest.toml"), "rb") as f:
            self.m = tomllib.load(f)

    def test_required_keys_and_formats(self):
        m = self.m
        for key in REQUIRED:
            self.assertIn(key, m, key)
        self.assertEqual(m["schema_version"], "1.0.0")
        self.assertRegex(m["id"], r"^[a-z][a-z0-9_]*$")  # a Python identifier, lower case
        self.assertRegex(m["version"], SEMVER)
        self.assertRegex(m["blender_version_min"], SEMVER)
        self.assertGreaterEqual(tuple(int(x) for x in m["blender_version_min"].split(".")), (4, 2, 0))
        self.assertEqual(m["type"], "add-on")
        self.assertLessEqual(len(m["tagline"]), 64)
        self.assertNotRegex(m["tagline"], r"[.!?,;:]$")  # no trailing punctuation
        self.assertTrue(all(lic.startswith("SPDX:") for lic in m["license"]))
        self.assertIn("SPDX:GPL-3.0-or-later", m["license"])
        self.assertTrue(set(m.get("tags", [])) <= ADDON_TAGS, m.get("tags"))
        self.assertTrue(set(m.get("platforms", [])) <= PLATFORMS, m.get("platforms"))

    def test_agrees_with_bl_info_and_the_project(self):
        info = bl_info()
        self.assertEqual(self.m["name"], info["name"])
        self.assertEqual(self.m["version"], ".".join(str(x) for x in info["version"]))
        if PROJECT_VERSION:
            self.assertEqual(self.m["version"], PROJECT_VERSION)
        self.assertEqual(self.m["maintainer"], info["author"])


ZIP = os.environ.get("CAGEKIT_ADDON_ZIP")


@unittest.skipUnless(ZIP, "CAGEKIT_ADDON_ZIP not set (ctest packaging.blender_zip.manifest sets it)")
class ZipManifest(unittest.TestCase):
    def setUp(self):
        with zipfile.ZipFile(ZIP) as z:
            self.names = [n for n in z.namelist() if not n.endswith("/")]
            self.m = tomllib.loads(z.read("cagekit_blender/blender_manifest.toml").decode())
        with open(os.path.join(ADDON, "blender_manifest.toml"), "rb") as f:
            self.source = tomllib.load(f)

    def test_build_paths_list_every_file_and_every_bundled_library(self):
        self.assertTrue(all(n.startswith("cagekit_blender/") for n in self.names), self.names)
        files = sorted(n[len("cagekit_blender/"):] for n in self.names)
        build = self.m["build"]
        self.assertNotIn("paths_exclude_pattern", build)  # replaced by the explicit list
        self.assertEqual(sorted(build["paths"]), files)
        self.assertTrue(any(re.fullmatch(r"cagekit/libcagekit\.so\.\d+", f) for f in files), files)
        libs = [f for f in files if f.startswith("cagekit/libs/")]
        self.assertGreater(len(libs), 0, "no bundled library in the zip")
        self.assertTrue(all(re.fullmatch(r"cagekit/libs/lib[^/]+\.so(\.[0-9a-z]+)+", f) for f in libs), libs)
        self.assertEqual(self.m["platforms"], ["linux-x64"])  # native libraries: one platform

    def test_the_rest_is_the_source_manifest(self):
        strip = lambda m: {k: v for k, v in m.items() if k != "build"}  # noqa: E731
        self.assertEqual(strip(self.m), strip(self.source))


if __name__ == "__main__":
    unittest.main(verbosity=2)
