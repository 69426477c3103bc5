# SPDX-License-Identifier: GPL-3.0-or-later
"""Load proof of a bundled cagekit package: which file each library of its closure was loaded from,
read in /proc/self/maps of the running process (ctest packaging.wheel.venv, packaging.wheel.blender).

    before = load_proof.mapped()       # before `import cagekit`
    import cagekit; ...one call...
    load_proof.check(os.path.dirname(cagekit.__file__), before, host="Blender")

Every library of libcagekit's closure in the package (libcagekit and the PACKAGE/libs/* it needs;
libs/ also holds what only the bundled CLI in bin/ needs) must be mapped exactly once,
from the package, unless the host process had a library of the same SONAME mapped before the import:
the loader then reuses the host's copy (a SONAME is loaded once per process), and the library is
reported as shared with the host. Everything else coming from outside the package is a failure.
Also runnable as a script in a Python where cagekit is installed: it does the import and one call.
"""
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, ".."))  # packaging/: bundle_libs (the ELF reader)
import bundle_libs  # noqa: E402


def mapped():
    """{path: SONAME} of every shared object mapped into this process (/proc/self/maps)."""
    out = {}
    with open("/proc/self/maps") as f:
        for line in f:
            parts = line.split(None, 5)
            if len(parts) < 6:
                continue
            path = parts[5].strip()
            if not path.startswith("/") or ".so" not in os.path.basename(path) or path in out:
                continue
            try:
                out[path] = bundle_libs.elf_dynamic(path)["soname"] or os.path.basename(path)
            except (OSError, ValueError):
                continue
    return out


def library_closure(package_dir):
    """libcagekit's SONAME and those of the bundled libraries it needs, directly or not (read from
    the ELF files of the package: libs/ also holds what only the bundled CLI in bin/ needs)."""
    libs_dir = os.path.join(package_dir, bundle_libs.LIBS_DIR)
    todo = sorted(f for f in os.listdir(package_dir) if f.startswith("libcagekit.so"))
    seen = list(todo)
    while todo:
        name = todo.pop()
        path = os.path.join(package_dir if name.startswith("libcagekit.so") else libs_dir, name)
        for needed in bundle_libs.elf_dynamic(path)["needed"]:
            if needed not in seen and os.path.isfile(os.path.join(libs_dir, needed)):
                seen.append(needed)
                todo.append(needed)
    return sorted(seen)


def check(package_dir, before, host="the interpreter", shared_out=None):
    """Prints where each bundled library came from; returns the list of failures (empty: passed).
    The SONAMEs shared with the host are appended to shared_out when given."""
    package_dir = os.path.realpath(package_dir)
    libs_dir = os.path.join(package_dir, bundle_libs.LIBS_DIR)
    bundled = library_closure(package_dir)
    cli_only = sorted(set(os.listdir(libs_dir)) - set(bundled))
    now = mapped()
    failures, from_bundle, shared = [], [], []
    for soname in bundled:
        paths = sorted(p for p, s in now.items() if s == soname)
        inside = [p for p in paths if os.path.realpath(p).startswith(package_dir + os.sep)]
        outside = [p for p in paths if p not in inside]
        if not paths:
            failures.append("%s: bundled but not loaded" % soname)
        elif inside and outside:
            failures.append("%s: loaded twice, from the package and from %s" % (soname, outside))
        elif inside:
            from_bundle.append("%s  (%s)" % (soname, os.path.relpath(inside[0], package_dir)))
        elif all(p in before for p in outside):
            shared.append("%s  (%s, loaded by %s before import cagekit)" % (soname, outside[0], host))
            if shared_out is not None:
                shared_out.append(soname)
        else:
            failures.append("%s: loaded from %s, outside the package, and not loaded by %s before the import"
                            % (soname, outside, host))
    print("load proof in %s (pid %d), package %s:" % (host, os.getpid(), package_dir))
    print("  loaded from the bundle (%d): %s" % (len(from_bundle), "; ".join(from_bundle) or "none"))
    print("  shared with %s (%d): %s" % (host, len(shared), "; ".join(shared) or "none"))
    print("  for the bundled CLI only (bin/, not the library's; %d): %s" % (len(cli_only), "; ".join(cli_only) or "none"))
    for f in failures:
        print("  FAIL " + f)
    return failures


def main():
    before = mapped()
    import cagekit
    mesh = cagekit.Mesh.from_bytes(CUBE_OBJ, "obj")
    refined = cagekit.Cage(mesh).subdivide(2)  # OpenSubdiv's CPU refiner
    counts = refined.mesh().counts()
    print("cagekit %s from %s; cube subdivided twice: %s" % (cagekit.version(), cagekit.__file__, counts))
    failures, shared = [], []
    if counts[1] != 6 * 16:
        failures.append("subdivided cube has %s faces, expected 96" % (counts[1],))
    expected = os.environ.get("CAGEKIT_EXPECT_PREFIX")
    if expected and not os.path.realpath(cagekit.__file__).startswith(os.path.realpath(expected) + os.sep):
        failures.append("cagekit imported from %s, not from under %s" % (cagekit.__file__, expected))
    host = os.path.basename(sys.executable)
    failures += check(os.path.dirname(cagekit.__file__), before, host=host, shared_out=shared)
    # A plain interpreter may share only what its own executable NEEDs (Debian's python3.11: libz).
    own = set(bundle_libs.elf_dynamic(os.path.realpath(sys.executable))["needed"])
    for soname in shared:
        if soname not in own:
            failures.append("%s: shared with %s but not NEEDED by %s itself" % (soname, host, sys.executable))
    if failures:
        print("load proof FAILED:\n  " + "\n  ".join(failures))
    else:
        print("load proof: every bundled library but those NEEDED by %s itself (%s) was loaded from the package"
              % (host, ", ".join(sorted(shared)) or "none"))
    return 1 if failures else 0


CUBE_OBJ = (b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n"
            b"f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n")

if __name__ == "__main__":
    sys.exit(main())
