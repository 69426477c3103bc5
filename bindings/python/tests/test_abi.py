# SPDX-License-Identifier: GPL-3.0-or-later
"""The ctypes declarations match include/cagekit/cagekit.h; loading and version checks."""
import ctypes
import os
import re
import shutil
import subprocess
import sys
import tempfile
import unittest

import support  # noqa: F401  (puts the package on sys.path)

import cagekit
from cagekit import _lib

HEADER = os.path.join(support.HERE, "..", "..", "..", "include", "cagekit", "cagekit.h")
GL_HEADER = os.path.join(os.path.dirname(HEADER), "cagekit_gl.h")


def header_text():
    """The public headers (the main one and the GL binding) without their comments."""
    text = ""
    for path in (HEADER, GL_HEADER):
        with open(path) as f:
            text += re.sub(r"/\*.*?\*/", "", f.read(), flags=re.S)
    return text


def header_functions():
    """name -> parameter count of every CAGEKIT_API function in the header."""
    text = header_text()
    out = {}
    for m in re.finditer(r"CAGEKIT_API\s+[^;(]*?\b(cagekit_\w+)\s*\(([^)]*)\)\s*;", text):
        params = m.group(2).strip()
        out[m.group(1)] = 0 if params in ("", "void") else params.count(",") + 1
    return out


class DeclarationsMatchTheHeader(unittest.TestCase):
    def test_every_function_is_declared_with_its_parameter_count(self):
        functions = header_functions()
        self.assertGreater(len(functions), 90)
        self.assertEqual(sorted(set(functions) - set(_lib.PROTOTYPES)), [], "functions without a prototype")
        self.assertEqual(sorted(set(_lib.PROTOTYPES) - set(functions)), [], "prototypes not in the header")
        for name, count in functions.items():
            self.assertEqual(len(_lib.PROTOTYPES[name][1]), count, name)
            self.assertEqual(getattr(_lib.lib, name).argtypes, _lib.PROTOTYPES[name][1], name)

    def test_every_struct_is_declared_with_the_header_fields(self):
        text = header_text()
        structs = re.findall(r"typedef struct (cagekit_\w+) \{", text)
        self.assertEqual(sorted(set(structs)), sorted(_lib.STRUCTS))

    def test_struct_layouts_match_a_c_compiler(self):
        cc = os.environ.get("CC") or shutil.which("cc") or shutil.which("gcc") or shutil.which("clang")
        if not cc:
            self.skipTest("no C compiler to compare the struct layouts with")
        lines = ["#include <cagekit/cagekit.h>", "#include <cagekit/cagekit_gl.h>", "#include <stddef.h>",
                 "#include <stdio.h>", "int main(void) {"]
        expected = []
        for cname, cls in sorted(_lib.STRUCTS.items()):
            lines.append('  printf("%%s %%zu\\n", "%s", sizeof(%s));' % (cname, cname))
            expected.append("%s %d" % (cname, ctypes.sizeof(cls)))
            for field in cls._fields_:
                lines.append('  printf("%%s %%zu\\n", "%s.%s", offsetof(%s, %s));' % (cname, field[0], cname,
                                                                                       field[0]))
                expected.append("%s.%s %d" % (cname, field[0], getattr(cls, field[0]).offset))
        lines += ["  return 0;", "}"]
        with tempfile.TemporaryDirectory() as tmp:
            source, exe = os.path.join(tmp, "layout.c"), os.path.join(tmp, "layout")
            with open(source, "w") as f:
                f.write("\n".join(lines) + "\n")
            subprocess.run([cc, "-std=c99", "-I", os.path.join(os.path.dirname(HEADER), ".."), source, "-o", exe],
                           check=True)
            actual = subprocess.run([exe], check=True, capture_output=True, text=True).stdout.split("\n")
        self.assertEqual([a for a in actual if a], expected)


class Loading(unittest.TestCase):
    def test_versions(self):
        self.assertEqual(cagekit.abi_version(), cagekit.ABI_VERSION)
        self.assertRegex(cagekit.version(), r"^\d+\.\d+\.\d+$")
        self.assertTrue(os.path.exists(cagekit.library_path) or "/" not in cagekit.library_path)

    def _python(self, code, **env):
        environment = dict(os.environ, PYTHONPATH=os.path.dirname(support.HERE), **env)
        return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=environment)

    def test_a_bad_library_path_is_a_clear_import_error(self):
        r = self._python("import cagekit", CAGEKIT_LIBRARY="/nonexistent/libcagekit.so")
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("ImportError: cagekit: CAGEKIT_LIBRARY=/nonexistent/libcagekit.so cannot be loaded", r.stderr)

    def test_imports_without_numpy_and_says_how_to_install_it(self):
        code = ("import sys; sys.modules['numpy'] = None\n"
                "import cagekit\n"
                "m = cagekit.Mesh.from_bytes(b'v 0 0 0\\nv 1 0 0\\nv 0 1 0\\nf 1 2 3\\n', 'obj')\n"
                "print(m.counts(), len(m.to_bytes('ply')) > 0)\n"
                "try:\n"
                "    m.positions\n"
                "except ImportError as e:\n"
                "    print('ImportError', e)\n")
        r = self._python(code)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("(3, 1, 3) True", r.stdout)
        self.assertIn("ImportError cagekit needs numpy", r.stdout)
        self.assertIn("python3-numpy", r.stdout)


if __name__ == "__main__":
    unittest.main()
