# SPDX-License-Identifier: GPL-3.0-or-later
"""The package's own structure: its modules import each other in one direction only, and none
but _lib.py changes _lib's state or declares argtypes on shared function objects."""
import ast
import os
import sys
import unittest

import support  # noqa: F401  (puts the package on sys.path)

import cagekit

PACKAGE = os.path.dirname(cagekit.__file__)


def modules():
    """module name -> parsed source of every module of the package but __init__."""
    out = {}
    for name in sorted(os.listdir(PACKAGE)):
        if name.endswith(".py") and name != "__init__.py":
            with open(os.path.join(PACKAGE, name)) as f:
                out[name[:-3]] = ast.parse(f.read(), name)
    return out


def type_checking_only(node):
    """`if TYPE_CHECKING:` (or typing.TYPE_CHECKING): its body runs for type checkers only."""
    test = node.test if isinstance(node, ast.If) else None
    return (isinstance(test, ast.Name) and test.id == "TYPE_CHECKING") or (
        isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING")


def package_imports(tree, names):
    """(module imported, line, inside a function or class) for each import of one of `names`
    (relative imports: `from . import a`, `from .a import b`) that runs: the imports under
    `if TYPE_CHECKING:` (for annotations naming a class of a module above) are left out."""
    found = []

    def children(node):
        for child in ast.iter_child_nodes(node):
            if type_checking_only(child):
                yield from child.orelse  # the run-time branch only
            else:
                yield child

    def visit(node, nested):
        for child in children(node):
            if isinstance(child, ast.ImportFrom) and child.level == 1:
                targets = [child.module] if child.module else [a.name for a in child.names]
                found.extend((t, child.lineno, nested) for t in targets if t in names)
            visit(child, nested or isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)))
    visit(tree, False)
    return found


class Imports(unittest.TestCase):
    def test_no_import_inside_a_function(self):
        # A deferred import is how a cycle hides: each module imports its dependencies at the top.
        trees = modules()
        nested = ["%s.py:%d imports %s" % (m, line, t) for m, tree in trees.items()
                  for t, line, inside in package_imports(tree, trees) if inside]
        self.assertEqual(nested, [])

    def test_the_import_graph_has_no_cycle(self):
        trees = modules()
        graph = {m: sorted({t for t, _, _ in package_imports(tree, trees)}) for m, tree in trees.items()}
        state, path = {}, []

        def visit(m):  # depth first; a module met again while on the path closes a cycle
            state[m] = "open"
            path.append(m)
            for t in graph[m]:
                if state.get(t) == "open":
                    self.fail("import cycle: " + " -> ".join(path[path.index(t):] + [t]))
                if t not in state:
                    visit(t)
            path.pop()
            state[m] = "done"
        for m in graph:
            if m not in state:
                visit(m)
        self.assertIn("fit", graph["cage"])  # Cage.fit: cage -> fit, and not back
        self.assertNotIn("cage", graph["fit"])


# remesh.py still adds its structs and prototypes to _lib's dicts and declares them on _lib.lib; it
# is being moved to the limit_patches.py form (its own STRUCTS, PROTOTYPES and _lib.Functions)
# with the header's new remesh structs (issue 22). Remove it from here then.
STILL_PATCHING = set()
MUTATORS = {"update", "setdefault", "pop", "popitem", "clear", "append", "extend", "_declare"}


def _root(node):
    """The name an attribute / subscript chain starts from (`_lib` for _lib.lib.f.argtypes)."""
    while isinstance(node, (ast.Attribute, ast.Subscript)):
        node = node.value
    return node.id if isinstance(node, ast.Name) else None


def patches(tree):
    """(line, what) for each place the module changes _lib's state or declares a function."""
    found = []
    for node in ast.walk(tree):
        targets = (node.targets if isinstance(node, ast.Assign) else
                   [node.target] if isinstance(node, (ast.AugAssign, ast.AnnAssign)) else [])
        for target in targets:
            for t in (target.elts if isinstance(target, ast.Tuple) else [target]):
                if isinstance(t, (ast.Attribute, ast.Subscript)) and _root(t) == "_lib":
                    found.append((node.lineno, "assigns into _lib"))
                elif isinstance(t, ast.Attribute) and t.attr in ("argtypes", "restype"):
                    found.append((node.lineno, "sets %s" % t.attr))
        if isinstance(node, ast.Call):
            f = node.func
            if isinstance(f, ast.Attribute) and f.attr in MUTATORS and _root(f) == "_lib":
                found.append((node.lineno, "calls _lib...%s" % f.attr))
            if isinstance(f, ast.Name) and f.id in ("setattr", "delattr") and node.args and \
                    _root(node.args[0]) == "_lib":
                found.append((node.lineno, "%s on _lib" % f.id))
    return found


class Declarations(unittest.TestCase):
    def test_no_module_but_lib_changes_lib_or_declares_shared_functions(self):
        # A module declaring a part of the header keeps STRUCTS, PROTOTYPES and a _lib.Functions
        # of its own (limit_patches.py): importing it changes no other module's declarations.
        found = ["%s.py:%d %s" % (m, line, what) for m, tree in modules().items()
                 if m != "_lib" and m not in STILL_PATCHING for line, what in patches(tree)]
        self.assertEqual(found, [])
        for m, tree in modules().items():
            if m in STILL_PATCHING:
                self.assertNotEqual(patches(tree), [], "%s.py no longer patches _lib: remove it from "
                                    "STILL_PATCHING" % m)

    def test_a_module_declares_on_its_own_function_objects(self):
        from cagekit import _lib
        patches_module = sys.modules["cagekit.limit_patches"]
        mine = patches_module.lib.cagekit_limit_patches_create
        self.assertIsNot(mine, getattr(_lib.lib, "cagekit_limit_patches_create"))
        self.assertEqual(mine.argtypes, patches_module.PROTOTYPES["cagekit_limit_patches_create"][1])
        self.assertNotIn("cagekit_limit_patches_create", _lib.PROTOTYPES)
        self.assertNotIn("cagekit_scan_to_cage_options", _lib.STRUCTS)


if __name__ == "__main__":
    unittest.main()
