# SPDX-License-Identifier: GPL-3.0-or-later
"""The type hints of the public API (the package ships py.typed).

Every public function of cagekit.__all__ and every public method, property, constructor and
class/static method of its exported classes has every parameter (but self/cls) and its return
annotated, and typing.get_type_hints resolves them (no broken forward reference). With mypy
importable (Debian: python3-mypy), the package must also type-check without errors."""
import enum
import importlib.util
import inspect
import os
import tempfile
import typing
import unittest

import support  # noqa: F401  (puts the package under test on sys.path)

import cagekit

PACKAGE = "cagekit"


def _ours(obj):
    return (getattr(obj, "__module__", None) or "").split(".")[0] == PACKAGE


def _public_callables():
    """(qualified name, function, skip-first-parameter) of the public API."""
    out = []
    for name in cagekit.__all__:
        obj = getattr(cagekit, name)
        if inspect.isfunction(obj):
            if _ours(obj):
                out.append(("cagekit." + name, obj, False))
        elif inspect.isclass(obj) and _ours(obj):
            seen = set()
            for klass in obj.__mro__:
                if not _ours(klass):
                    continue  # object, int, Exception, Enum, ...: not this package's API
                for attr, value in vars(klass).items():
                    if attr in seen:
                        continue
                    seen.add(attr)
                    if attr.startswith("_") and attr != "__init__":
                        continue
                    where = "cagekit.%s.%s" % (name, attr)
                    if isinstance(value, property):
                        for kind, fn in (("getter", value.fget), ("setter", value.fset)):
                            if fn is not None:
                                out.append(("%s (%s)" % (where, kind), fn, True))
                    elif isinstance(value, staticmethod):
                        out.append((where, value.__func__, False))
                    elif isinstance(value, classmethod):
                        out.append((where, value.__func__, True))
                    elif inspect.isfunction(value):
                        out.append((where, value, True))
                    # other attributes: enum members, class constants (not callables)
    return out


def missing_annotations(fn, skip_first):
    """The problems of one function's annotations ([] when complete and resolvable)."""
    problems = []
    try:
        hints = typing.get_type_hints(fn)
    except Exception as e:  # a forward reference that does not resolve, a bad expression
        return ["get_type_hints fails: %s: %s" % (type(e).__name__, e)]
    params = list(inspect.signature(fn).parameters.values())
    if skip_first and params and params[0].name in ("self", "cls"):
        params = params[1:]
    for p in params:
        if p.name not in hints:
            star = {p.VAR_POSITIONAL: "*", p.VAR_KEYWORD: "**"}.get(p.kind, "")
            problems.append("parameter %s%s not annotated" % (star, p.name))
    if "return" not in hints:
        problems.append("return not annotated")
    return problems


class TypeHints(unittest.TestCase):
    def test_checker_finds_gaps(self):
        """The check itself: an unannotated parameter, *args, a return and a broken forward
        reference are each reported."""
        def f(self, a: int, b, *args, **kwargs: int):
            pass

        def g(x: "NoSuchName") -> None:  # noqa: F821
            pass

        problems = missing_annotations(f, True)
        self.assertEqual(problems, ["parameter b not annotated", "parameter *args not annotated",
                                    "return not annotated"])
        self.assertTrue(missing_annotations(g, False)[0].startswith("get_type_hints fails: NameError"))

        def h(a: int, *args: str, **kwargs: float) -> None:
            pass

        self.assertEqual(missing_annotations(h, False), [])

    def test_public_api_is_annotated(self):
        callables = _public_callables()
        names = {name for name, _, _ in callables}
        # The walk reaches what it should: functions, methods, constructors, properties (both
        # sides), class methods and inherited Handle methods.
        for expected in ("cagekit.fit", "cagekit.render", "cagekit.Mesh.from_arrays", "cagekit.Cage.__init__",
                         "cagekit.Cage.positions (getter)", "cagekit.Cage.boundary_rule (setter)",
                         "cagekit.Context.progress (setter)", "cagekit.Hierarchy.close",
                         "cagekit.LimitSurfaces.evaluate", "cagekit.CpuDeformer.deform",
                         "cagekit.RenderScene.add", "cagekit.CageKitError.__init__", "cagekit.Record.as_dict"):
            self.assertIn(expected, names)
        self.assertGreater(len(callables), 120)
        failures = []
        for name, fn, skip_first in callables:
            for problem in missing_annotations(fn, skip_first):
                failures.append("%s: %s" % (name, problem))
        self.assertEqual(failures, [], "\n" + "\n".join(failures))

    def test_enums_are_int_enums(self):
        """The option enumerations take the documented ints (annotations say Union[Enum, int, str])."""
        for name in cagekit.__all__:
            obj = getattr(cagekit, name)
            if inspect.isclass(obj) and issubclass(obj, enum.Enum):
                self.assertTrue(issubclass(obj, int), name)

    def test_py_typed_is_shipped(self):
        self.assertTrue(os.path.isfile(os.path.join(os.path.dirname(cagekit.__file__), "py.typed")))

    def test_mypy(self):
        """mypy finds no error in the package (skipped when mypy is not installed)."""
        if importlib.util.find_spec("mypy") is None:
            self.skipTest("mypy is not installed (Debian: apt install python3-mypy)")
        # In process (mypy.api), not `sys.executable -m mypy`: inside a host (Blender) sys.executable
        # may be another interpreter, without mypy.
        from mypy import api
        package = os.path.dirname(os.path.abspath(cagekit.__file__))
        with tempfile.TemporaryDirectory() as cache:
            stdout, stderr, status = api.run(["--ignore-missing-imports", "--no-error-summary", "--cache-dir", cache,
                                              "--hide-error-context", package])
        self.assertEqual(status, 0, "mypy reports errors:\n" + stdout + stderr)


if __name__ == "__main__":
    unittest.main()
