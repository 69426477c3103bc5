#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""NEEDED-closure check of a bundled cagekit package (ctest packaging.*.closure).

    python3 check_bundle.py PATH [PATH ...]

Each PATH is a package folder (cagekit/), a wheel (.whl), a folder holding one wheel, or a zip (the Blender add-on); archives are
unpacked into a scratch folder first. Checked, from the ELF dynamic sections (packaging/bundle_libs.py
reads them; no readelf or loader involved):
  - the package holds libcagekit under its SONAME and at least one bundled library;
  - every shared object has a RUNPATH made only of $ORIGIN-relative entries (no RPATH, no absolute
    path of the build machine);
  - every NEEDED entry of every shared object is on the allowlist (glibc, libstdc++, libgcc_s,
    GL dispatch) or is found through its RUNPATH inside the package, as a file whose SONAME is that
    name;
  - every bundled library is needed by something (nothing dead is shipped);
  - the executables in bin/ (the wheel's CLI) are executable; their NEEDED entries are checked as
    above (libcagekit and the bundled libraries through their RUNPATH);
  - every bundled library is listed in licenses/BUNDLED.txt with its package's copyright file.
Exit status 0 when every check passes, 1 with one line per failure otherwise.
"""
import os
import sys
import tempfile
import zipfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bundle_libs  # noqa: E402


def package_dirs(root):
    """Every folder under root that holds a libcagekit.so.* file (the package folders)."""
    out = []
    for dirpath, _dirs, files in os.walk(root):
        if any(f.startswith("libcagekit.so") for f in files):
            out.append(dirpath)
    return out


def check_package(pkg):
    failures, report = [], []
    objects = []
    for dirpath, _dirs, files in os.walk(pkg):
        for f in sorted(files):
            path = os.path.join(dirpath, f)
            if (".so" in f or os.path.basename(dirpath) == bundle_libs.BIN_DIR) and bundle_libs.is_elf(path):
                objects.append(path)
    mains = [p for p in objects if os.path.basename(p).startswith("libcagekit.so")]
    if len(mains) != 1:
        failures.append("%s: expected one libcagekit.so.*, found %s" % (pkg, mains))
    executables = [p for p in objects if os.path.basename(os.path.dirname(p)) == bundle_libs.BIN_DIR]
    for exe in executables:
        if not os.access(exe, os.X_OK):
            failures.append("%s: not executable" % os.path.relpath(exe, pkg))
        report.append("%s: executable" % os.path.relpath(exe, pkg))
    bundled = [p for p in objects if p not in mains and p not in executables]
    if not bundled:
        failures.append("%s: no bundled library next to libcagekit" % pkg)
    used = set()
    pkg_real = os.path.realpath(pkg)
    for obj in objects:
        rel = os.path.relpath(obj, pkg)
        dyn = bundle_libs.elf_dynamic(obj)
        if dyn["rpath"]:
            failures.append("%s: has DT_RPATH %s (expected a RUNPATH only)" % (rel, dyn["rpath"]))
        if obj in bundled and dyn["soname"] != os.path.basename(obj):
            failures.append("%s: file name is not its SONAME (%s)" % (rel, dyn["soname"]))
        dirs = []
        for entry in dyn["runpath"]:
            if not entry.startswith("$ORIGIN"):
                failures.append("%s: RUNPATH entry %r is not $ORIGIN-relative" % (rel, entry))
                continue
            dirs.append(os.path.realpath(entry.replace("$ORIGIN", os.path.dirname(obj), 1)))
        for name in dyn["needed"]:
            if bundle_libs.allowed(name):
                report.append("%s: %s -> system (allowlist)" % (rel, name))
                continue
            hit = None
            for d in dirs:
                cand = os.path.join(d, name)
                if os.path.isfile(cand):
                    hit = cand
                    break
            if hit is None:
                failures.append("%s: NEEDED %s is neither allowlisted nor found through RUNPATH %s inside the "
                                "package" % (rel, name, dyn["runpath"]))
                continue
            if not os.path.realpath(hit).startswith(pkg_real + os.sep):
                failures.append("%s: NEEDED %s resolves outside the package: %s" % (rel, name, hit))
                continue
            if bundle_libs.elf_dynamic(hit)["soname"] != name:
                failures.append("%s: NEEDED %s resolves to %s whose SONAME differs" % (rel, name, hit))
            used.add(os.path.realpath(hit))
            report.append("%s: %s -> %s" % (rel, name, os.path.relpath(hit, pkg)))
    for b in bundled:
        if os.path.realpath(b) not in used:
            failures.append("%s: bundled but needed by nothing" % os.path.relpath(b, pkg))
    # The notices: licenses/BUNDLED.txt names each bundled library with a copyright file present.
    listing = os.path.join(pkg, bundle_libs.LICENSES_DIR, "BUNDLED.txt")
    named = {}
    if os.path.isfile(listing):
        with open(listing) as f:
            for line in f:
                if line.strip() and not line.startswith("#"):
                    soname, package = line.split()[:2]
                    named[soname] = package
    for b in bundled:
        package = named.get(os.path.basename(b))
        if package is None:
            failures.append("%s: not listed in %s" % (os.path.relpath(b, pkg), os.path.relpath(listing, pkg)))
        elif not os.path.isfile(os.path.join(pkg, bundle_libs.LICENSES_DIR, package + ".copyright")):
            failures.append("%s: no %s/%s.copyright" % (os.path.relpath(b, pkg), bundle_libs.LICENSES_DIR, package))
        else:
            report.append("%s: licence %s/%s.copyright" % (os.path.relpath(b, pkg), bundle_libs.LICENSES_DIR, package))
    return failures, report, len(objects)


def main(argv):
    if len(argv) < 2:
        sys.stderr.write(__doc__)
        return 2
    failures = []
    with tempfile.TemporaryDirectory(prefix="cagekit-bundle-") as scratch:
        for i, path in enumerate(argv[1:]):
            root = path
            if os.path.isdir(path) and not package_dirs(path):  # a dist folder: its one wheel
                wheels = [os.path.join(path, f) for f in os.listdir(path) if f.endswith(".whl")]
                if len(wheels) != 1:
                    failures.append("%s: expected one wheel, found %s" % (path, wheels))
                    continue
                path = root = wheels[0]
            if zipfile.is_zipfile(path):
                root = os.path.join(scratch, str(i))
                with zipfile.ZipFile(path) as z:
                    z.extractall(root)
                    for info in z.infolist():  # the modes the archive records (pip installs with them)
                        mode = (info.external_attr >> 16) & 0o777
                        if mode and not info.is_dir():
                            os.chmod(os.path.join(root, info.filename), mode)
            pkgs = package_dirs(root)
            if len(pkgs) != 1:
                failures.append("%s: expected one package folder with libcagekit, found %s" % (path, pkgs))
                continue
            f, report, count = check_package(pkgs[0])
            print("%s: %d shared objects in %s" % (path, count, os.path.relpath(pkgs[0], root)))
            for line in report:
                print("  " + line)
            failures += ["%s: %s" % (path, x) for x in f]
    for x in failures:
        print("FAIL " + x)
    print("closure: %s" % ("FAILED (%d)" % len(failures) if failures else "every NEEDED entry resolves inside the "
                           "package or to the allowlist"))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
