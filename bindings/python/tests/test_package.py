# SPDX-License-Identifier: GPL-3.0-or-later
"""The package's own structure: its modules import each other in one direction only."""
import ast
import os
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


def package_imports(tree, names):
    """(module imported, line, inside a function or class) for each import of one of `names`
    (relative imports: `from . import a`, `from .a import b`)."""
    found = []

    def visit(node, nested):
        for child in ast.iter_child_nodes(node):
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


if __name__ == "__main__":
    unittest.main()
