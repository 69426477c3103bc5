# SPDX-License-Identifier: GPL-3.0-or-later
"""Checks that the C++ layer wraps every C entry point.

Lists the functions the C headers declare (CAGEKIT_API ... cagekit_NAME(...);) and requires each
name to appear in the code of the matching C++ header (comments and string literals removed, so
a name only mentioned in a comment or in an error message does not count). Usage:
  check_hpp_coverage.py INCLUDE_DIR/cagekit
"""
import re
import sys
from pathlib import Path

# C header -> the C++ header that must wrap it.
PAIRS = {"cagekit.h": "cagekit.hpp", "cagekit_gl.h": "cagekit_gl.hpp"}

# Functions deliberately not wrapped, with the reason. Keep it empty when possible.
NOT_WRAPPED = {}


def strip_comments_and_strings(text: str) -> str:
    pattern = re.compile(r'//[^\n]*|/\*.*?\*/|"(?:\\.|[^"\\])*"|\'(?:\\.|[^\'\\])*\'', re.S)
    return pattern.sub(lambda m: " " if m.group(0)[0] in "/" else '""', text)


def declared_functions(header: str) -> list:
    code = strip_comments_and_strings(header)
    return re.findall(r"CAGEKIT_API\s[^;()]*?\b(cagekit_[a-z0-9_]+)\s*\(", code)


def main() -> int:
    folder = Path(sys.argv[1])
    failures = 0
    total = 0
    for c_name, cpp_name in PAIRS.items():
        functions = declared_functions((folder / c_name).read_text())
        if not functions:
            print(f"FAIL {c_name}: no CAGEKIT_API function found (the pattern is out of date)")
            failures += 1
        cpp_code = strip_comments_and_strings((folder / cpp_name).read_text())
        for function in functions:
            total += 1
            if function in NOT_WRAPPED:
                print(f"skip {function}: {NOT_WRAPPED[function]}")
                continue
            if not re.search(r"\b" + function + r"\b", cpp_code):
                print(f"FAIL {function} ({c_name}) is not called in {cpp_name}")
                failures += 1
    for function in NOT_WRAPPED:
        if not any(function in declared_functions((folder / c).read_text()) for c in PAIRS):
            print(f"FAIL {function} is listed as not wrapped but is no longer declared")
            failures += 1
    print(f"{total} C functions, {len(NOT_WRAPPED)} deliberately not wrapped, {failures} failures")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
