# SPDX-License-Identifier: GPL-3.0-or-later
"""The `cagekit` console script of the wheel: runs the `cagekit` CLI bundled in the package
(cagekit/bin/cagekit, with libcagekit and its libraries beside it; packaging/make_wheel.py puts it
there). The process is replaced (os.execv): exit status, signals and stdio are the CLI's own.
A source checkout has no bundled CLI: then this says so and exits 127, as a shell does for a
missing command."""
import os
import sys

__all__ = ["bundled_cli", "main"]


def bundled_cli():
    """The path of the CLI bundled with this package, or None (a source checkout)."""
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "bin", "cagekit")
    return path if os.path.isfile(path) and os.access(path, os.X_OK) else None


def main():
    cli = bundled_cli()
    if cli is None:
        sys.stderr.write("cagekit: this cagekit package has no bundled CLI (%s/bin/cagekit); install the wheel, or "
                         "build the CLI (samples/cli) and run it directly\n" % os.path.dirname(os.path.abspath(__file__)))
        return 127
    sys.stdout.flush()
    sys.stderr.flush()
    os.execv(cli, [cli] + sys.argv[1:])
    return 127  # not reached: execv replaces the process or raises OSError


if __name__ == "__main__":
    sys.exit(main())
