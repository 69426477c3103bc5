#!/bin/sh
# The `cagekit` usage comes from its CLI11 parser: every command's --help exits 0 and names the
# options the command accepts, usage errors exit 64 with one 'cagekit: ...' line and a hint to
# --help, and README.md's CLI section names the same options as the parser.
# usage: check_cli_help.sh CAGEKIT README.md
#
# README rule (mechanical): the CLI section is README.md from the line '## CLI' to the next '## '
# heading; in its first ``` code block, the block of command C starts at each line beginning with
# 'cagekit C' and runs to the next line beginning with 'cagekit ' or to the end of the code block
# (a command may have several blocks). For every command, the set of '--option' words in its
# blocks must equal the set of options its --help lists, leaving out --help and --quiet; --quiet,
# which every command but version takes, must be named in the section once.
set -u
cli="$1"; readme="$2"
exec /usr/bin/env python3 - "$cli" "$readme" <<'PY'
import re, subprocess, sys

cli, readme = sys.argv[1], sys.argv[2]
passed = failures = 0
def check(ok, name, detail=""):
    global passed, failures
    if ok:
        passed += 1; print(f"[ OK   ] {name}")
    else:
        failures += 1; print(f"[ FAIL ] {name}" + (f": {detail}" if detail else ""))

def run(*args):
    p = subprocess.run([cli, *args], capture_output=True, text=True)
    return p.returncode, p.stdout, p.stderr

# The options each command accepted before its parser moved to CLI11 (the interface, fixed here).
expected = {
    "info": "--json --quiet",
    "convert": "--bits --speed --ascii --quiet",
    "subdivide": "--levels --limit --quiet",
    "simplify": "--faces --vertices --cage --clusters --creases --feature-angle --crease-angle --input-crease-angle "
                "--epsilon --contour-tolerance --json --quiet",
    "remesh": "--method --tolerance --max-face-valence --curvature-radius --edge-length --regions --region-tolerance "
              "--weights --refinement-passes --feature-angle --threads --json --quiet",
    "fit": "--passes --tolerance --projection --fairing --crease-feature-reach --keep-creases --threads --json --quiet",
    "pipeline": "--method --faces --vertices --creases --feature-angle --crease-angle --input-crease-angle --passes "
                "--tolerance --projection --fairing --crease-feature-reach --keep-creases --threads "
                "--max-face-valence --curvature-radius --edge-length --regions --region-tolerance --weights "
                "--refinement-passes --fit-tolerance --limit-levels --no-repair --components --weld-tolerance "
                "--no-fallback --two-sided-refit --json --quiet",
    "batch": "--method --faces --vertices --creases --feature-angle --crease-angle --input-crease-angle --passes "
             "--tolerance --projection --fairing --crease-feature-reach --keep-creases --threads "
             "--max-face-valence --curvature-radius --edge-length --regions --region-tolerance --weights "
             "--refinement-passes --fit-tolerance --limit-levels --no-repair --components --weld-tolerance "
             "--no-fallback --two-sided-refit --jobs --timeout --memory-limit --resume --retry-failed --thumbnails --order --json "
             "--quiet",
    "bind": "--local-frame --exact-normals --sharp-angle --threads --json --quiet",
    "deform": "--local-frame --sharp-angle --json --quiet",
    "bench-deform": "--frames --moved --threads --vertex-order --json --quiet",
    "render": "--mesh --cage --deformed --error --views --size --wire --creases --level --colormap --title --quiet",
    "demo": "--quiet",
    "export-surfaces": "--tolerance --max-level --per --sewing-tolerance --knot-removal --schema --threads --check --quiet",
    "version": "",
}
expected = {c: set(o.split()) for c, o in expected.items()}
option_line = re.compile(r"^\s+(?:-h,)?(--[a-z][a-z0-9-]*)")

# 1. cagekit --help lists every command; no arguments: usage on stderr, exit 64.
code, out, err = run("--help")
listed = set(re.findall(r"^  ([a-z][a-z-]*)\s", out.split("Subcommands:")[-1], re.M))
check(code == 0 and listed == set(expected), "cagekit --help: exit 0, lists every command",
      f"exit {code}, listed {sorted(listed)}")
code, out, err = run()
check(code == 64 and out == "" and "Usage: cagekit" in err, "cagekit without arguments: usage on stderr, exit 64")

# 2. COMMAND --help: exit 0, the usage of that command, exactly its options.
help_options = {}
for command, options in expected.items():
    code, out, err = run(command, "--help")
    found = {m.group(1) for m in map(option_line.match, out.splitlines()) if m} - {"--help"}
    help_options[command] = found
    check(code == 0 and f"Usage: cagekit {command} " in out and found == options,
          f"{command} --help: exit 0, its usage, names each of its options",
          f"exit {code}, missing {sorted(options - found)}, unexpected {sorted(found - options)}")

# 3. Usage errors: 'cagekit: ...' and a hint to --help on stderr, exit 64.
for args, what in ((["bogus"], "unknown command"), (["fit", "a", "b", "c", "--bogus"], "unknown option"),
                   (["fit", "a", "b"], "missing positional")):
    code, out, err = run(*args)
    lines = err.splitlines()
    check(code == 64 and len(lines) == 2 and lines[0].startswith("cagekit: ") and "--help" in lines[1],
          f"usage error ({what}): one 'cagekit:' line and a hint to --help, exit 64", f"exit {code}: {err!r}")

# 4. README.md's CLI section names the parser's options (rule in the header of this script).
text = open(readme, encoding="utf-8").read()
section = re.search(r"^## CLI\n(.*?)(?=^## )", text, re.M | re.S)
check(section is not None, "README.md has a '## CLI' section")
section = section.group(1) if section else ""
block = re.search(r"^```\n(.*?)^```", section, re.M | re.S)
block = block.group(1) if block else ""
readme_options = {c: set() for c in expected}
current = None
for line in block.splitlines():
    if line.startswith("cagekit "):
        name = line.split()[1]
        current = name if name in expected else None
        check(current is not None, f"README CLI block: '{name}' is a command")
    if current:
        readme_options[current] |= set(re.findall(r"--[a-z][a-z0-9-]*", line))
for command in expected:
    documented = readme_options[command] - {"--quiet"}
    parsed = help_options[command] - {"--quiet"}
    has_block = any(l.startswith(f"cagekit {command}") for l in block.splitlines())
    check(has_block and documented == parsed, f"README CLI section, {command}: the options of its --help",
          f"not in README: {sorted(parsed - documented)}, not in --help: {sorted(documented - parsed)}")
check("--quiet" in section and all("--quiet" in help_options[c] for c in expected if c != "version"),
      "--quiet: taken by every command but version, named in README's CLI section")

print(f"{passed} passed, {failures} failed")
sys.exit(1 if failures else 0)
PY
