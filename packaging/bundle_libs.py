#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Bundles libcagekit and every non-system shared library it needs into a package folder.

Used by the Python wheel (packaging/make_wheel.py, CMake target python_wheel) and by the Blender
add-on zip (bindings/blender/make_addon_zip.cmake), so that both carry the same files:

    PACKAGE/libcagekit.so.N          libcagekit under its SONAME (cagekit/_lib.py looks there first
                                     after CAGEKIT_LIBRARY), RUNPATH $ORIGIN/libs
    PACKAGE/libs/<SONAME>            each library of the NEEDED closure that is not on ALLOWLIST,
                                     under its SONAME, RUNPATH $ORIGIN
    PACKAGE/bin/<name>               optional executables (the wheel's `cagekit` CLI), RUNPATH
                                     $ORIGIN/..:$ORIGIN/../libs; their closure is bundled too

    PACKAGE/licenses/<package>.copyright   the Debian copyright file of each bundled library's
                                     package, and licenses/BUNDLED.txt: SONAME, package, version

The folder is libs/, not a hidden .libs/: Blender's extension tools leave out hidden paths by
default. The closure is resolved on the build machine with ldd (the loader's own search); the copies get
their RUNPATH from patchelf. Libraries on ALLOWLIST (glibc, the C++ runtime, the GL dispatch
libraries) are left to the system: every Linux that runs Blender has them, and the GL ones must be
the machine's own driver's.

    python3 bundle_libs.py LIBRARY PACKAGE_DIR SONAME [EXECUTABLE ...]   prints one line per bundled file

The module also holds a small ELF reader (dynamic section: NEEDED, SONAME, RUNPATH/RPATH), used by
packaging/check_bundle.py to check the result without trusting the tools that made it.
"""
import os
import re
import shutil
import struct
import subprocess
import sys

LIBS_DIR = "libs"

# Resolved from the system, never bundled (by SONAME prefix).
ALLOWLIST = (
    # glibc
    "libc.so.", "libm.so.", "libdl.so.", "libpthread.so.", "librt.so.", "libutil.so.", "libresolv.so.",
    "libmvec.so.", "libanl.so.", "ld-linux", "linux-vdso.so.", "linux-gate.so.",
    # the C++ / GCC runtime
    "libstdc++.so.", "libgcc_s.so.",
    # GL dispatch (libglvnd): the machine's driver
    "libGL.so.", "libEGL.so.", "libOpenGL.so.", "libGLX.so.", "libGLdispatch.so.", "libGLESv2.so.",
)


def allowed(soname):
    """True when `soname` is resolved from the system (on ALLOWLIST)."""
    return os.path.basename(soname).startswith(ALLOWLIST)


# --- ELF dynamic section ----------------------------------------------------------------------
DT_NULL, DT_NEEDED, DT_STRTAB, DT_SONAME, DT_RPATH, DT_RUNPATH = 0, 1, 5, 14, 15, 29
PT_LOAD, PT_DYNAMIC = 1, 2


def is_elf(path):
    try:
        with open(path, "rb") as f:
            return f.read(4) == b"\x7fELF"
    except OSError:
        return False


def elf_dynamic(path):
    """{'needed': [...], 'soname': str or None, 'runpath': [...], 'rpath': [...]} read from the
    PT_DYNAMIC segment of an ELF shared object (32/64-bit, either byte order)."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:4] != b"\x7fELF":
        raise ValueError("%s: not an ELF file" % path)
    is64 = data[4] == 2
    end = "<" if data[5] == 1 else ">"
    if is64:
        e_phoff, = struct.unpack_from(end + "Q", data, 0x20)
        e_phentsize, e_phnum = struct.unpack_from(end + "HH", data, 0x36)
        ph_fmt, dyn_fmt = end + "IIQQQQQQ", end + "qQ"
    else:
        e_phoff, = struct.unpack_from(end + "I", data, 0x1C)
        e_phentsize, e_phnum = struct.unpack_from(end + "HH", data, 0x2A)
        ph_fmt, dyn_fmt = end + "IIIIIIII", end + "iI"
    loads, dynamic = [], None
    for i in range(e_phnum):
        fields = struct.unpack_from(ph_fmt, data, e_phoff + i * e_phentsize)
        if is64:
            p_type, _flags, p_offset, p_vaddr, _paddr, p_filesz, _memsz, _align = fields
        else:
            p_type, p_offset, p_vaddr, _paddr, p_filesz, _memsz, _flags, _align = fields
        if p_type == PT_LOAD:
            loads.append((p_vaddr, p_offset, p_filesz))
        elif p_type == PT_DYNAMIC:
            dynamic = (p_offset, p_filesz)
    out = {"needed": [], "soname": None, "runpath": [], "rpath": []}
    if dynamic is None:
        return out
    entries, strtab = [], None
    size = struct.calcsize(dyn_fmt)
    for off in range(dynamic[0], dynamic[0] + dynamic[1], size):
        tag, val = struct.unpack_from(dyn_fmt, data, off)
        if tag == DT_NULL:
            break
        if tag == DT_STRTAB:
            strtab = val
        entries.append((tag, val))

    def file_offset(vaddr):  # DT_STRTAB is a virtual address
        for v, o, sz in loads:
            if v <= vaddr < v + sz:
                return vaddr - v + o
        raise ValueError("%s: DT_STRTAB outside every PT_LOAD" % path)

    base = file_offset(strtab)

    def string(off):
        start = base + off
        return data[start:data.index(b"\0", start)].decode()

    for tag, val in entries:
        if tag == DT_NEEDED:
            out["needed"].append(string(val))
        elif tag == DT_SONAME:
            out["soname"] = string(val)
        elif tag == DT_RUNPATH:
            out["runpath"] = string(val).split(":")
        elif tag == DT_RPATH:
            out["rpath"] = string(val).split(":")
    return out


# --- resolving and copying --------------------------------------------------------------------
_LDD_LINE = re.compile(r"^\s*(\S+)\s+=>\s+(\S+)\s+\(0x[0-9a-f]+\)\s*$")


def resolve_closure(library):
    """{soname: path as ldd prints it} of every library in the NEEDED closure of `library`, as the
    loader resolves them on this machine (ldd). A NEEDED entry ldd cannot find is an error."""
    r = subprocess.run(["ldd", library], capture_output=True, text=True)
    if r.returncode != 0:
        raise RuntimeError("ldd %s failed: %s" % (library, r.stderr.strip()))
    found = {}
    for line in r.stdout.splitlines():
        if "not found" in line:
            raise RuntimeError("ldd %s: %s" % (library, line.strip()))
        m = _LDD_LINE.match(line)
        if m:
            found[m.group(1)] = m.group(2)
    return found


def patchelf():
    tool = shutil.which("patchelf")
    if not tool:
        raise RuntimeError("patchelf not found (Debian package patchelf; packaging/install-deps.sh installs it)")
    return tool


def set_runpath(path, runpath):
    subprocess.run([patchelf(), "--set-rpath", runpath, path], check=True)
    got = elf_dynamic(path)
    if got["runpath"] != runpath.split(":") or got["rpath"]:
        raise RuntimeError("%s: RUNPATH %s after patchelf, expected %s" % (path, got["runpath"], runpath))


LICENSES_DIR = "licenses"


def debian_package(paths):
    """(package, version) owning the first of `paths` dpkg knows (tried as given and with /usr
    added or removed: Debian 12 is merged-/usr, its packages are not all), or None."""
    if not shutil.which("dpkg-query"):
        return None
    tried = []
    for p in paths:
        tried += [p, p[len("/usr"):] if p.startswith("/usr/") else "/usr" + p]
    for p in tried:
        r = subprocess.run(["dpkg-query", "-S", p], capture_output=True, text=True)
        if r.returncode == 0 and ":" in r.stdout:
            name = r.stdout.split(":", 1)[0].strip()
            v = subprocess.run(["dpkg-query", "-W", "-f=${Version}", name], capture_output=True, text=True)
            return name, v.stdout.strip()
    return None


def write_licenses(package_dir, origins):
    """PACKAGE/licenses/: the copyright file of each bundled library's Debian package and
    BUNDLED.txt (SONAME, package, version, source path). An error when one cannot be found: a
    binary is not redistributed without its notices."""
    out = os.path.join(package_dir, LICENSES_DIR)
    if os.path.isdir(out):
        shutil.rmtree(out)
    os.makedirs(out)
    lines = ["# Libraries bundled with libcagekit (packaging/bundle_libs.py): SONAME, Debian package, version, "
             "source path.", "# Their copyright and licence terms: <package>.copyright here."]
    for soname, (ldd_path, real) in sorted(origins.items()):
        pkg = debian_package([ldd_path, real])
        if pkg is None:
            raise RuntimeError("no Debian package (dpkg-query -S) owns %s: its licence cannot be bundled" % real)
        name, version = pkg
        name = name.split(":")[0]
        copyright_file = "/usr/share/doc/%s/copyright" % name
        if not os.path.isfile(copyright_file):
            raise RuntimeError("%s (for %s) not found" % (copyright_file, soname))
        shutil.copyfile(copyright_file, os.path.join(out, name + ".copyright"))
        lines.append("%s %s %s %s" % (soname, name, version, real))
    with open(os.path.join(out, "BUNDLED.txt"), "w") as f:
        f.write("\n".join(lines) + "\n")


BIN_DIR = "bin"


def bundle(library, package_dir, soname, executables=()):
    """Copies `library` as package_dir/soname, each of `executables` into package_dir/bin, and the
    non-allowlisted NEEDED closure of all of them into package_dir/libs, with $ORIGIN RUNPATHs.
    An executable finds libcagekit (under `soname`, one folder up) and the bundled libraries through
    its RUNPATH. Returns the bundled paths relative to package_dir."""
    patchelf()  # fail before copying anything
    libs = os.path.join(package_dir, LIBS_DIR)
    bins = os.path.join(package_dir, BIN_DIR)
    for d in (libs, bins):
        if os.path.isdir(d):
            shutil.rmtree(d)
    os.makedirs(libs)
    main = os.path.join(package_dir, soname)
    shutil.copyfile(os.path.realpath(library), main)
    os.chmod(main, 0o755)
    bundled, origins = [soname], {}
    closure = resolve_closure(library)
    if executables:
        os.makedirs(bins)
    for exe in executables:
        target = os.path.join(bins, os.path.basename(exe))
        shutil.copyfile(os.path.realpath(exe), target)
        os.chmod(target, 0o755)
        set_runpath(target, "$ORIGIN/..:$ORIGIN/../" + LIBS_DIR)
        bundled.append(BIN_DIR + "/" + os.path.basename(exe))
        for name, path in resolve_closure(exe).items():
            if name != soname:  # libcagekit itself: the copy above, not the build tree's
                closure.setdefault(name, path)
    for name, path in sorted(closure.items()):
        if allowed(name):
            continue
        real_soname = elf_dynamic(path)["soname"] or name
        origins[real_soname] = (path, os.path.realpath(path))
        target = os.path.join(libs, real_soname)
        shutil.copyfile(path, target)
        os.chmod(target, 0o755)
        set_runpath(target, "$ORIGIN")
        bundled.append(LIBS_DIR + "/" + real_soname)
    set_runpath(main, "$ORIGIN/" + LIBS_DIR)
    write_licenses(package_dir, origins)
    return bundled


def main(argv):
    if len(argv) < 4:
        sys.stderr.write("usage: bundle_libs.py LIBRARY PACKAGE_DIR SONAME [EXECUTABLE ...]\n")
        return 2
    try:
        for rel in bundle(argv[1], argv[2], argv[3], argv[4:]):
            print(rel)
    except (RuntimeError, OSError, subprocess.CalledProcessError) as e:
        sys.stderr.write("bundle_libs.py: %s\n" % e)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
