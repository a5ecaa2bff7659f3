#!/usr/bin/env python3
"""include_cycles.py: the include graph of the host headers (host/**/*.h, included by their path
below host/) and its cycles; also every file under host/passes, host/plan or host/cl that
includes something from host/verify (verification stays out of production code).

    python3 scripts/include_cycles.py        # exit status 1 when it finds either
"""
import os
import re
import sys

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "host")
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)


def includes(path):
    with open(path, encoding="utf-8", errors="replace") as f:
        return INCLUDE.findall(f.read())


def main():
    files = []
    for d, _, names in os.walk(ROOT):
        for n in names:
            if n.endswith((".h", ".c", ".cpp")):
                files.append(os.path.relpath(os.path.join(d, n), ROOT))
    headers = {f for f in files if f.endswith(".h")}
    graph = {h: [i for i in includes(os.path.join(ROOT, h)) if i in headers] for h in headers}

    cycles, state, stack = [], {}, []

    def visit(h):  # depth-first; a grey node met again closes a cycle
        state[h] = 1
        stack.append(h)
        for i in sorted(graph[h]):
            if state.get(i) == 1:
                cycles.append(stack[stack.index(i):] + [i])
            elif i not in state:
                visit(i)
        stack.pop()
        state[h] = 2

    for h in sorted(headers):
        if h not in state:
            visit(h)
    for c in cycles:
        print("cycle: " + " -> ".join(c))

    leaks = []
    for f in sorted(files):
        if f.split(os.sep)[0] in ("passes", "plan", "cl"):
            leaks += [(f, i) for i in includes(os.path.join(ROOT, f)) if i.startswith("verify/")]
    for f, i in leaks:
        print("verification in production code: host/%s includes %s" % (f, i))
    print("%d headers, %d cycles, %d verify includes" % (len(headers), len(cycles), len(leaks)))
    return 1 if cycles or leaks else 0


if __name__ == "__main__":
    sys.exit(main())
