# SPDX-License-Identifier: GPL-3.0-or-later
"""The ctypes declarations match include/cagekit/cagekit.h; loading and version checks."""
import ast
import ctypes
import importlib
import inspect
import os
import pkgutil
import re
import shutil
import subprocess
import sys
import tempfile
import unittest

import support  # noqa: F401  (puts the package on sys.path)

import cagekit
from cagekit import _formats, _lib

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


def _declared(attribute):
    """C name -> (module, value) of every entry of the dict `attribute` (STRUCTS or PROTOTYPES)
    of each module of the package that has one: _lib's core and the modules that declare their
    part of the header themselves, found without a list here."""
    out = {}
    for info in pkgutil.iter_modules(cagekit.__path__):
        module = importlib.import_module("cagekit." + info.name)
        for cname, value in getattr(module, attribute, {}).items():
            if out.setdefault(cname, (module, value))[1] is not value:
                raise AssertionError("%s is declared twice (%s, %s)" % (cname, out[cname][0].__name__,
                                                                        module.__name__))
    return out


def declared_structs():
    """C name -> ctypes class of every struct the package declares."""
    return {cname: cls for cname, (module, cls) in _declared("STRUCTS").items()}


def declared_functions():
    """C name -> (the module's function table `lib`, (restype, argtypes)) of every function the
    package declares."""
    return {name: (module.lib, prototype) for name, (module, prototype) in _declared("PROTOTYPES").items()}


def _evaluate(expr, constants):
    """The value of a C constant expression of the header: integer and floating literals with
    their suffixes, names of constants, unary -, binary | << + - *; anything else raises."""
    expr = re.sub(r"\b((?:0[xX][0-9a-fA-F]+)|\d+)[uUlL]+\b", r"\1", expr.strip())
    expr = re.sub(r"(?<![\w.])(\d*\.\d*(?:[eE][-+]?\d+)?|\d+[eE][-+]?\d+)[fF]\b", r"\1", expr)  # not 0x1f
    operators = {ast.BitOr: lambda a, b: a | b, ast.LShift: lambda a, b: a << b, ast.Add: lambda a, b: a + b,
                 ast.Sub: lambda a, b: a - b, ast.Mult: lambda a, b: a * b}

    def value(node):
        if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)):
            return node.value
        if isinstance(node, ast.Name):
            return constants[node.id]
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub):
            return -value(node.operand)
        if isinstance(node, ast.BinOp) and type(node.op) in operators:
            return operators[type(node.op)](value(node.left), value(node.right))
        raise ValueError("not a constant expression: %s" % expr)
    return value(ast.parse(expr, mode="eval").body)


def header_constants(text):
    """name -> value of the header's enum constants and of its #defines that are numbers."""
    constants = {}
    for name, expr in re.findall(r"^#define\s+(CAGEKIT_\w+)[ \t]+([^{\n]+)$", text, flags=re.M):
        try:
            constants[name] = _evaluate(expr, constants)
        except (ValueError, KeyError, SyntaxError, TypeError):
            pass  # a macro that is no number (CAGEKIT_API, version strings, ...)
    for body in re.findall(r"\benum\s*\w*\s*\{(.*?)\}", text, flags=re.S):  # typedef or anonymous
        following = 0
        for item in filter(None, (i.strip() for i in body.split(","))):
            name, _, expr = item.partition("=")
            constants[name.strip()] = following = _evaluate(expr, constants) if expr.strip() else following
            following += 1
    return constants


def _split_top_level(items):
    """The comma-separated entries of an initializer list, commas inside ( ) or { } kept."""
    out, depth, current = [], 0, ""
    for ch in items:
        depth += (ch in "({") - (ch in ")}")
        if ch == "," and depth == 0:
            out.append(current.strip())
            current = ""
        else:
            current += ch
    if current.strip():
        out.append(current.strip())
    return out


def header_initializers():
    """CAGEKIT_*_INIT macro name -> list of its entries: ("sizeof", type name), None for NULL,
    the number (enum constants and #defines resolved), or a tuple of numbers for an array field."""
    text = header_text().replace("\\\n", " ")  # one line per macro
    constants = header_constants(text)
    out = {}
    for name, items in re.findall(r"^#define\s+(CAGEKIT_\w+_INIT)\s+\{(.*)\}\s*$", text, flags=re.M):
        entries = []
        for item in _split_top_level(items):
            size = re.fullmatch(r"sizeof\s*\(\s*(\w+)\s*\)", item)
            if item.startswith("{") and item.endswith("}"):  # an array field: a list of its elements
                entries.append(tuple(_evaluate(e, constants) for e in _split_top_level(item[1:-1])))
                continue
            entries.append(("sizeof", size.group(1)) if size else None if item == "NULL" else
                           _evaluate(item, constants))
        out[name] = entries
    return out


def _plain(value):
    """A field's value as Python compares it: function pointers by address (None for NULL)."""
    if isinstance(value, ctypes._CFuncPtr):
        return ctypes.cast(value, ctypes.c_void_p).value
    if isinstance(value, ctypes.Array):
        return tuple(_plain(v) for v in value)
    return value


def init_macro(cname):
    """cagekit_fit_options -> CAGEKIT_FIT_OPTIONS_INIT."""
    return "CAGEKIT_%s_INIT" % cname[len("cagekit_"):].upper()


class DeclarationsMatchTheHeader(unittest.TestCase):
    def test_every_function_is_declared_with_its_parameter_count(self):
        functions = header_functions()
        declared = declared_functions()
        self.assertGreater(len(functions), 90)
        self.assertEqual(sorted(set(functions) - set(declared)), [], "functions without a prototype")
        self.assertEqual(sorted(set(declared) - set(functions)), [], "prototypes not in the header")
        for name, count in functions.items():
            table, (restype, argtypes) = declared[name]
            self.assertEqual(len(argtypes), count, name)
            self.assertEqual(getattr(table, name).argtypes, argtypes, name)  # the object the module calls
            self.assertEqual(getattr(table, name).restype, restype, name)

    def test_every_struct_is_declared_with_the_header_fields(self):
        text = header_text()
        structs = re.findall(r"typedef struct (cagekit_\w+) \{", text)
        self.assertEqual(sorted(set(structs)), sorted(declared_structs()))

    def test_struct_defaults_are_the_header_initializers(self):
        # Each declared struct with a CAGEKIT_<NAME>_INIT macro: new() (what every function sends
        # to C when the caller leaves an option out) equals the macro's list mapped onto the
        # fields in declaration order, entries left out being zero as in C.
        structs = declared_structs()
        initializers = header_initializers()
        by_macro = {init_macro(cname): cname for cname in structs}
        self.assertEqual(sorted(set(initializers) - set(by_macro)), [], "INIT macros of undeclared structs")
        with_defaults = [c for c, cls in structs.items() if getattr(cls, "_defaults", None)]
        self.assertEqual(sorted(c for c in with_defaults if init_macro(c) not in initializers), [],
                         "Python defaults without an INIT macro to check them against")
        self.assertGreater(len(initializers), 10)
        for macro, entries in sorted(initializers.items()):
            cname = by_macro[macro]
            cls = structs[cname]
            fields = [f[0] for f in cls._fields_]
            self.assertLessEqual(len(entries), len(fields), macro)
            actual, zero = cls.new(), cls()
            for k, field in enumerate(fields):
                entry = entries[k] if k < len(entries) else None
                if isinstance(entry, tuple) and entry[:1] == ("sizeof",):
                    self.assertEqual(entry[1], cname, "%s: sizeof of another struct" % macro)
                    expected = ctypes.sizeof(cls)
                elif entry is None:  # NULL, or an entry the list leaves out: zero
                    expected = _plain(getattr(zero, field))
                else:  # through the field's C type, as the compiler converts the constant
                    probe = cls()
                    setattr(probe, field, entry)
                    expected = _plain(getattr(probe, field))
                self.assertEqual(_plain(getattr(actual, field)), expected,
                                 "%s.%s: Python default != %s entry %d" % (cname, field, macro, k))

    def test_keyword_defaults_are_the_struct_defaults(self):
        # The functions' keyword defaults are read from the structs' defaults(); this catches a
        # literal written into a signature again. (callable, struct, {parameter: field} where the
        # names differ); parameters named as no field of the struct are not compared.
        # (the package's names limit_patches, limit_surfaces and scan_to_cage are the functions, not
        # the modules)
        limit_patches, limit_surfaces, scan_to_cage, remesh = (
            importlib.import_module("cagekit." + m) for m in ("limit_patches", "limit_surfaces", "scan_to_cage", "remesh"))
        cases = [
            (cagekit.Context.__init__, _lib.ContextDesc, {}), (cagekit.Mesh.repair, _lib.RepairOptions, {}),
            (cagekit.Mesh.write, _lib.WriteOptions, {}), (cagekit.Mesh.to_bytes, _lib.WriteOptions, {}),
            (cagekit.Cage.write, _lib.WriteOptions, {}), (cagekit.Cage.to_bytes, _lib.WriteOptions, {}),
            (cagekit.Cage.subdivide, _lib.SubdivideOptions, {}), (cagekit.Cage.surface, _lib.SurfaceOptions, {}),
            (cagekit.Hierarchy.__init__, _lib.SimplifyOptions, {}), (cagekit.simplify, _lib.SimplifyOptions, {}),
            (cagekit.Hierarchy.build_cage, _lib.CageOptions, {}), (cagekit.fit, _lib.FitOptions, {}),
            (cagekit.bind, _lib.BindOptions, {}),
            (cagekit.LimitPatches.__init__, limit_patches.LimitPatchOptions, {}),
            (cagekit.limit_patches, limit_patches.LimitPatchOptions, {}),
            (cagekit.LimitSurfaces.__init__, limit_surfaces.LimitSurfaceOptions, {}),
            (cagekit.limit_surfaces, limit_surfaces.LimitSurfaceOptions, {}),
            (cagekit.scan_to_cage, scan_to_cage.ScanToCageOptions, {"faces": "target"}),
            (cagekit.scan_to_cage, _lib.CageOptions, {}),
            (cagekit.remesh_anisotropic, remesh.AnisotropicOptions, {}),
            (cagekit.remesh_quad, remesh.QuadRemeshOptions, {}),
        ]
        for function, struct, renamed in cases:
            defaults = struct.defaults()
            compared = 0
            for name, parameter in inspect.signature(function).parameters.items():
                field = renamed.get(name, name)
                if field not in defaults or parameter.default is inspect.Parameter.empty:
                    continue
                value = parameter.default
                if field == "crease_rule":  # names in Python
                    value = _lib.crease_rule_value(value)
                elif field == "format":
                    value = int(_formats.file_format(value))
                self.assertEqual(value, _plain(defaults[field]), "%s(%s=): default != %s.defaults()[%r]"
                                 % (function.__qualname__, name, struct.__name__, field))
                compared += 1
            self.assertGreater(compared, 0, function.__qualname__)

    def test_struct_layouts_match_a_c_compiler(self):
        cc = os.environ.get("CC") or shutil.which("cc") or shutil.which("gcc") or shutil.which("clang")
        if not cc:
            self.skipTest("no C compiler to compare the struct layouts with")
        lines = ["#include <cagekit/cagekit.h>", "#include <cagekit/cagekit_gl.h>", "#include <stddef.h>",
                 "#include <stdio.h>", "int main(void) {"]
        expected = []
        for cname, cls in sorted(declared_structs().items()):
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
        # the folder that holds the package under test (bindings/python, or the installed wheel's)
        environment = dict(os.environ, PYTHONPATH=os.path.dirname(os.path.dirname(cagekit.__file__)), **env)
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
