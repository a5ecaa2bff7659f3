#!/usr/bin/env python3
"""check_layers.py: the layering rules of host/ (docs: issue #17), checked from the sources.

1. No include cycles among the host headers (host/**/*.h, included by their path below host/).
2. Verification stays out of production code: nothing under host/passes, host/plan or host/cl
   includes a header from host/verify.
3. OpenCL API calls (cl*( ... ), not the cl_* types) appear only in host/cl/ and in the pass
   drivers named *_cl.c.
4. Kernel arguments are set only through host/cl/cl_args.h (clSetKernelArg in cl_args.c alone).

    python3 scripts/check_layers.py [HOST_DIR]   # prints each violation; exit 1 when there is one
"""
import os
import re
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = sys.argv[1] if len(sys.argv) > 1 else os.path.join(HERE, "..", "host")
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)
CL_CALL = re.compile(r"\bcl[A-Z]\w*\s*\(")
COMMENT_OR_STRING = re.compile(r'/\*.*?\*/|//[^\n]*|"(?:\\.|[^"\\\n])*"', re.S)


def read(rel):
    with open(os.path.join(ROOT, rel), encoding="utf-8", errors="replace") as f:
        return f.read()


def header_cycles(headers):
    graph = {h: [i for i in INCLUDE.findall(read(h)) if i in headers] for h in headers}
    cycles, state, stack = [], {}, []

    def visit(h):  # depth-first; meeting a header still on the stack closes a cycle
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
    return ["include cycle: " + " -> ".join(c) for c in cycles]


def main():
    files = []
    for d, _, names in os.walk(ROOT):
        for n in names:
            if n.endswith((".h", ".c", ".cpp")):
                files.append(os.path.relpath(os.path.join(d, n), ROOT).replace(os.sep, "/"))
    files.sort()
    headers = {f for f in files if f.endswith(".h")}
    problems = header_cycles(headers)
    for f in files:
        if f.split("/")[0] in ("passes", "plan", "cl"):
            problems += ["host/%s includes %s (verification in production code)" % (f, i)
                         for i in INCLUDE.findall(read(f)) if i.startswith("verify/")]
        code = COMMENT_OR_STRING.sub("", read(f))
        if f != "cl/cl_args.c" and re.search(r"\bclSetKernelArg\b", code):
            problems.append("host/%s calls clSetKernelArg (use cl/cl_args.h)" % f)
        if f.startswith("cl/") or f.endswith("_cl.c") or f.endswith(".h"):
            continue
        calls = sorted({m.group(0).rstrip("( ") for m in CL_CALL.finditer(code)})
        if calls:
            problems.append("host/%s calls OpenCL outside host/cl and *_cl.c: %s"
                            % (f, ", ".join(calls)))
    for p in problems:
        print(p)
    print("%d files, %d headers: %d problems" % (len(files), len(headers), len(problems)))
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
