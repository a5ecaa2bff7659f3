#!/usr/bin/env python3
"""check_docs.py: the docs cite only files that exist, and README's index lists every doc.

Scans README.md and docs/*.md for repository paths (in backticks or markdown links) that start
with a top-level folder of the tree (host/, kernels/, cpu/, test/, docs/, scripts/, data/) and
reports each one that does not exist; a path may name a file or a folder, may end in a
`:line` or `#anchor`, and a `*` or `{a,b}` pattern must match something. Exit 1 with one line per
problem."""
import glob
import os
import re
import sys

ROOTS = ("host/", "kernels/", "cpu/", "test/", "docs/", "scripts/", "data/")
TOKEN = re.compile(r"`([^`\s]+)`|\]\(([^)\s]+)\)")


def expand(p):
    m = re.search(r"\{([^}]*)\}", p)
    if not m:
        return [p]
    return [x for alt in m.group(1).split(",") for x in expand(p[: m.start()] + alt + p[m.end():])]


PLACEHOLDER = re.compile(r"(^|/)(X|P|NAME|PASS|STEM)([_./]|$)|_X\b|_NAME")


def exists(p):
    p = re.sub(r"[#:].*$", "", p).rstrip(".,;)")
    if not p or PLACEHOLDER.search(p):
        return True  # a pattern the text explains (kernels/X.cl), not a file
    m = re.match(r"^(.*)\.(\w+)/\.(\w+)$", p)  # "a.c/.h": a.c and a.h
    if m:
        return exists(m.group(1) + "." + m.group(2)) and exists(m.group(1) + "." + m.group(3))
    for q in expand(p):
        if any(c in q for c in "*?["):
            if not glob.glob(q):
                return False
        elif not os.path.exists(q):
            return False
    return True


def main():
    os.chdir(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
    bad = []
    files = ["README.md"] + sorted(glob.glob("docs/*.md"))
    for f in files:
        text = open(f, encoding="utf-8").read()
        for n, line in enumerate(text.splitlines(), 1):
            for a, b in TOKEN.findall(line):
                p = a or b
                if b and f.startswith("docs/") and not p.startswith(ROOTS) and p.endswith(".md"):
                    p = os.path.normpath(os.path.join("docs", p))  # a link relative to docs/
                if b and p.startswith("../"):
                    p = os.path.normpath(os.path.join(os.path.dirname(f), p))
                if not p.startswith(ROOTS) or "$" in p or "<" in p or "NNNN" in p:
                    continue
                if p.startswith(("data/cycles", "docs/results/")) and not os.path.exists("docs/results"):
                    continue
                if not exists(p):
                    bad.append(f"{f}:{n}: cites {p}, which does not exist")
    readme = open("README.md", encoding="utf-8").read()
    for d in sorted(glob.glob("docs/*.md")):
        if d not in readme:
            bad.append(f"README.md: the docs index does not list {d}")
    for b in bad:
        print(b)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
