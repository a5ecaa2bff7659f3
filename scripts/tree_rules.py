#!/usr/bin/env python3
"""tree_rules.py [ROOT]: checks the rules the source tree keeps (docs/design.md, "Rules").

Reads every #include and every OpenCL API call of the C/C++/OpenCL sources under ROOT (default:
the repository) and prints one line per rule, "PASS rule" or "FAIL rule: file: what", then exits
1 if any rule is broken. test/cli/test_tree.sh runs it on the tree and on small trees built to
break each rule (so every rule is shown to fail when broken).

Includes are resolved as the compiler does (the including file's folder, then -Ihost -Ikernels
-Icpu -Icpu/reference; -Itest for tests), so a rule speaks of real files, not spellings.
"""
import os
import re
import sys

ROOT = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), ".."))
SEARCH = ["host", "kernels", "cpu", "cpu/reference"]
SRC_EXT = (".c", ".h", ".cpp", ".cl", ".inc")
INCLUDE = re.compile(r'^\s*#\s*include\s*([<"])([^>"]+)[>"]', re.M)
# An OpenCL API call: clFoo( ... with the name starting "cl" + capital (clSetKernelArg,
# clEnqueueNDRangeKernel, ...). Comments are stripped first.
CL_CALL = re.compile(r"\bcl[A-Z][A-Za-z0-9]*\s*\(")
COMMENT = re.compile(r"/\*.*?\*/|//[^\n]*", re.S)
STRING = re.compile(r'"(?:\\.|[^"\\\n])*"')

# The fiber math the double-precision reference shares with the fast path (written once as
# .inc bodies, instantiated in double by fiber_common_d.h), and the K-buffer's compositing
# weights (the fragment reference composites exactly as the fast path does, so that only
# shading differs between them: docs/reference.md).
REFERENCE_SHARED_KERNEL_HEADERS = {
    "kernels/fiber_common_d.h", "kernels/fiber_common.inc", "kernels/fiber_params.h",
    "kernels/sl_compat.h", "kernels/kbuffer.h",
}


def rel(p):
    return os.path.relpath(p, ROOT)


def sources():
    out = []
    for top in ("host", "kernels", "cpu", "test"):
        for dp, dn, fn in os.walk(os.path.join(ROOT, top)):
            dn[:] = [d for d in dn if d != "corpus"]
            for f in fn:
                if f.endswith(SRC_EXT):
                    out.append(rel(os.path.join(dp, f)))
    return sorted(out)


def resolve(f, inc):
    dirs = [os.path.dirname(f)] + SEARCH + (["test"] if f.startswith("test/") else [])
    for d in dirs:
        p = os.path.normpath(os.path.join(d, inc))
        if os.path.isfile(os.path.join(ROOT, p)):
            return p
    return None


def main():
    files = sources()
    incs = {}  # file -> [(resolved project file or None, spelling, system?)]
    text = {}
    for f in files:
        src = open(os.path.join(ROOT, f), encoding="utf-8", errors="replace").read()
        text[f] = COMMENT.sub(" ", src)
        lst = []
        for m in INCLUDE.finditer(src):
            system = m.group(1) == "<"
            lst.append((None if system else resolve(f, m.group(2)), m.group(2), system))
        incs[f] = lst

    failures = {}

    def check(rule, ok, why):
        failures.setdefault(rule, [])
        if not ok:
            failures[rule].append(why)

    def under(p, *folders):
        return any(p == d or p.startswith(d + "/") for d in folders)

    for f in files:
        for tgt, spelled, system in incs[f]:
            if not system and tgt is None and not f.startswith("kernels/"):
                check("includes_resolve", False, f"{f}: \"{spelled}\" is no file of the tree")
            # 1. Kernels and their C twins never see the OpenCL runtime or the CLI.
            if under(f, "kernels", "cpu"):
                bad = (system and spelled.startswith("CL/")) or (
                    tgt is not None and under(tgt, "host/cl", "host/cli", "host/plan", "host/passes",
                                              "host/verify", "host/viewer"))
                check("twins_and_kernels_no_runtime_or_cli", not bad, f"{f} includes {spelled}")
            if f.startswith("kernels/") and tgt is not None:
                check("kernels_include_only_kernels", under(tgt, "kernels"), f"{f} includes {spelled}")
            # 2. The reference shares only the fiber math and the K-buffer weights.
            if under(f, "cpu/reference") and tgt is not None:
                ok = (under(tgt, "cpu/reference", "host/base", "host/scene", "host/io")
                      or tgt in REFERENCE_SHARED_KERNEL_HEADERS)
                check("reference_shares_only_fiber_math", ok, f"{f} includes {spelled}")
            if under(f, "host/verify/reference") and tgt is not None:
                # The fragment mode borrows the fast path's view pass (and the frame's K rule,
                # plan/frame.h) for the fragments it shades: the only door from the reference
                # into the fast path.
                ok = (under(tgt, "cpu/reference", "host/base", "host/scene", "host/io", "host/lighting",
                            "host/verify/reference") or tgt in REFERENCE_SHARED_KERNEL_HEADERS
                      or (f.endswith("reference_frag.c") and tgt in ("host/passes/view/frame_view.h", "host/plan/frame.h",
                                                          "host/cl/clrt.h")))
                check("reference_shares_only_fiber_math", ok, f"{f} includes {spelled}")
            # 3. Loaders know nothing of passes.
            if under(f, "host/scene", "host/io", "host/lighting", "host/base") and tgt is not None:
                bad = under(tgt, "host/plan", "host/passes", "host/verify", "host/cli", "host/viewer")
                check("loaders_know_no_passes", not bad, f"{f} includes {spelled}")
            # 4. Production code never includes the verification code or the CLI.
            if under(f, "host") and not under(f, "host/verify", "host/cli") and tgt is not None:
                check("production_excludes_verify", not under(tgt, "host/verify"), f"{f} includes {spelled}")
            # (the CLI's own tests and fuzz target test its helpers, so test/ may include it)
            if not under(f, "host/cli", "test") and tgt is not None:
                check("nothing_includes_cli", not under(tgt, "host/cli"), f"{f} includes {spelled}")
        # 5. OpenCL calls only in the runtime (host/cl) and the pass drivers (*_cl.c).
        if under(f, "host") and f.endswith((".c", ".cpp")):
            calls = CL_CALL.findall(STRING.sub('""', text[f]))
            ok = not calls or under(f, "host/cl") or f.endswith("_cl.c")
            check("opencl_calls_only_in_cl_and_drivers", ok, f"{f}: {len(calls)} OpenCL calls ({calls[0].rstrip('( ')}...)" if calls else f)
            # Kernel arguments go through host/cl/cl_args.h, which names the failing argument.
            sets = "clSetKernelArg(" in "".join(c.replace(" ", "") for c in calls)
            check("kernel_args_through_cl_args", not sets or f == "host/cl/cl_args.c",
                  f"{f} calls clSetKernelArg (use cl/cl_args.h: SL_CL_ARG)")
    for r in ("includes_resolve", "twins_and_kernels_no_runtime_or_cli", "kernels_include_only_kernels",
              "reference_shares_only_fiber_math", "loaders_know_no_passes", "production_excludes_verify",
              "nothing_includes_cli", "opencl_calls_only_in_cl_and_drivers", "kernel_args_through_cl_args"):
        failures.setdefault(r, [])

    # 6. No include cycles among the project's headers and sources.
    graph = {f: sorted({t for t, _, s in incs[f] if t}) for f in files}
    cycles = []
    state = {}
    stack = []

    def dfs(u):
        state[u] = 1
        stack.append(u)
        for v in graph.get(u, []):
            if state.get(v) == 1:
                cyc = stack[stack.index(v):] + [v]
                cycles.append(" -> ".join(cyc))
            elif v not in state:
                dfs(v)
        stack.pop()
        state[u] = 2

    sys.setrecursionlimit(10000)
    for f in files:
        if f not in state:
            dfs(f)
    failures["no_include_cycles"] = cycles

    # 6b. No cycles between folders either (a folder is a stage: host/plan, host/passes/light,
    # host/verify/checks, cpu, kernels, ...): the stages form a pipeline, so a folder that
    # includes another is never included back by it, directly or through others.
    def folder(p):
        parts = p.split("/")
        if parts[0] == "host":
            return "/".join(parts[:3]) if parts[1] in ("passes", "verify", "io") and len(parts) > 3 else "/".join(parts[:2])
        if parts[0] == "cpu":
            return "cpu/reference" if len(parts) > 2 and parts[1] == "reference" else "cpu"
        return parts[0]

    fgraph = {}
    for f in files:
        if f.startswith("test/"):
            continue
        for t in graph[f]:
            if folder(t) != folder(f):
                fgraph.setdefault(folder(f), {}).setdefault(folder(t), f"{f} includes {t}")
    fstate = {}
    fstack = []
    fcycles = []

    def fdfs(u):
        fstate[u] = 1
        fstack.append(u)
        for v in sorted(fgraph.get(u, {})):
            if fstate.get(v) == 1:
                ring = fstack[fstack.index(v):] + [v]
                fcycles.append(" -> ".join(ring) + " (" + "; ".join(
                    fgraph[a][b] for a, b in zip(ring, ring[1:])) + ")")
            elif v not in fstate:
                fdfs(v)
        fstack.pop()
        fstate[u] = 2

    for u in sorted(fgraph):
        if u not in fstate:
            fdfs(u)
    failures["no_folder_cycles"] = fcycles

    # 7. Tests mirror the sources: test/X/test_*.c sits beside a source folder host/X (or cl/ etc.).
    for f in files:
        if f.startswith("test/") and os.path.basename(f).startswith("test_") and f.endswith(".c"):
            d = os.path.dirname(f)[len("test/"):]
            if d in ("", "fuzz", "cli"):
                continue
            ok = os.path.isdir(os.path.join(ROOT, "host", d))
            check("tests_mirror_sources", ok, f"{f}: no folder host/{d}")
    failures.setdefault("tests_mirror_sources", [])

    # 8. A kernel is found by its stem: kernels/X.cl has a driver host/passes/P/X_cl.c, a C twin
    # cpu/X.c or cpu/X_c.c, and a test in test/passes/P/ whose file name or a TEST() name
    # holds X. The one exception is named here with its reason.
    TWIN_ELSEWHERE = {
        # the C evaluation of kernels/ms_response.h / ms_table.h lives beside the material's
        # response tables it reads (host/passes/volume/volume_ms.c, which depends on dual.h)
        "ms": "host/passes/volume/volume_ms.c",
    }
    failures.setdefault("kernels_found_by_stem", [])
    for f in files:
        if not (f.startswith("kernels/") and f.endswith(".cl")):
            continue
        stem = os.path.basename(f)[:-3]
        drivers = [g for g in files if re.fullmatch(r"host/passes/[a-z_]+/" + re.escape(stem) + r"_cl\.c", g)]
        if not drivers:
            check("kernels_found_by_stem", False, f"{f}: no driver host/passes/*/{stem}_cl.c")
            continue
        twin = TWIN_ELSEWHERE.get(stem)
        twins = [g for g in (f"cpu/{stem}.c", f"cpu/{stem}_c.c", twin) if g and g in files]
        check("kernels_found_by_stem", bool(twins), f"{f}: no twin cpu/{stem}.c or cpu/{stem}_c.c")
        pass_dir = "test/" + os.path.dirname(drivers[0])[len("host/"):]
        tests = [g for g in files if g.startswith(pass_dir + "/test_") and g.endswith(".c")]
        named = [g for g in tests if stem in os.path.basename(g)
                 or re.search(r"\bTEST\(\w*" + re.escape(stem), text[g])]
        check("kernels_found_by_stem", bool(named), f"{f}: no test in {pass_dir}/ names {stem}")

    bad = 0
    for rule in failures:
        if failures[rule]:
            bad += 1
            shown = failures[rule][:6]
            more = len(failures[rule]) - len(shown)
            print(f"FAIL {rule}: " + "; ".join(shown) + (f"; and {more} more" if more > 0 else ""))
        else:
            print(f"PASS {rule}")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
