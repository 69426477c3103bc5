# SPDX-License-Identifier: GPL-3.0-or-later
"""The installed headers' documentation follows one template per function (issue 22):

    /* What the call does (first sentence).
     * Ownership: who owns what it returns or keeps, and for how long (where anything crosses).
     * Errors: the status codes and when (or "none" for calls that cannot fail).
     * Threading: which objects it reads or modifies and from which threads it may be called. */

Every CAGEKIT_API declaration is covered by the comment right before it (or before the run of
declarations it belongs to, e.g. a retain / release pair) and that comment has an "Errors:" and
a "Threading:" line. The headers hold no repository paths and no benchmark figures.
Usage: check_header_docs.py HEADER...   (exit 1 listing every function that breaks the rule)
"""
import re
import sys

FORBIDDEN = [
    (re.compile(r"\b(?:sdk|tests|samples|bindings|shaders|packaging)/[\w/.-]+"), "a repository path"),
    (re.compile(r"\bRESULTS\.md\b|\bREADME(?:\.md)?\b"), "a repository document"),
    (re.compile(r"\b\d[\d.,]*\s*(?:fps|frames/s|MiB/s|GB/s|ms\b)|\b\d[\d.]*\s*[x×]\s+(?:faster|slower)"),
     "a benchmark figure"),
]


def declarations(text):
    """(name, comment before its run or None) for every CAGEKIT_API declaration."""
    out = []
    # Tokens in order: comments and CAGEKIT_API declarations; anything else (a typedef, a
    # #define, a struct) ends a run of declarations.
    token = re.compile(r"/\*.*?\*/|CAGEKIT_API\s+[^;]*?\b(cagekit_\w+)\s*\([^;]*?\)\s*;|[^\s]", re.S)
    comment, in_run = None, False
    for m in token.finditer(text):
        piece = m.group(0)
        if piece.startswith("/*"):
            comment, in_run = piece, False
        elif m.group(1):
            out.append((m.group(1), comment))
            in_run = True
        else:
            comment, in_run = None, False
    return out


def check(path):
    text = open(path, encoding="utf-8").read()
    problems = []
    for name, comment in declarations(text):
        if comment is None:
            problems.append("%s: %s has no documentation comment" % (path, name))
            continue
        for label in ("Errors:", "Threading:"):
            if label not in comment:
                problems.append("%s: %s: its comment has no '%s' line" % (path, name, label))
    for pattern, what in FORBIDDEN:
        for m in pattern.finditer(text):
            line = text.count("\n", 0, m.start()) + 1
            problems.append("%s:%d: %s in the installed header: %r" % (path, line, what, m.group(0)))
    return problems


def main(paths):
    problems = [p for path in paths for p in check(path)]
    for p in problems:
        print(p)
    print("%d problem(s) in %s" % (len(problems), ", ".join(paths)))
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
