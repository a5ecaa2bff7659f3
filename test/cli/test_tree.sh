#!/usr/bin/env bash
# test_tree.sh: the rules the source tree keeps (docs/design.md "Rules", scripts/tree_rules.py):
# first each rule on the real tree, then each rule on a small tree built to break it, which the
# checker must report (a rule that cannot fail is no rule).
. "$(dirname "$0")/lib.sh"
PY=${PYTHON:-python3}
if ! command -v "$PY" >/dev/null 2>&1; then skip tree_rules "no python3"; exit 0; fi
RULES=scripts/tree_rules.py

out=$("$PY" "$RULES" 2>&1)
rc=$?
printf '%s\n' "$out" | sed -n 's/^PASS \(.*\)/PASS tree_\1/p; s/^FAIL \([^:]*\): \(.*\)/FAIL tree_\1: \2/p'
if [ "$rc" -ne 0 ] && ! printf '%s' "$out" | grep -q '^FAIL'; then fail tree_rules_ran "exit $rc: $out"; fi

# broken NAME RULE FILE=CONTENT...: a tree holding just these files must FAIL RULE.
broken() {
    local name=$1 rule=$2; shift 2
    local d="$TMP/tree_$name"
    rm -rf "$d"; mkdir -p "$d/host" "$d/kernels" "$d/cpu/reference" "$d/test"
    local spec path
    for spec in "$@"; do
        path=${spec%%=*}
        mkdir -p "$d/$(dirname "$path")"
        printf '%b\n' "${spec#*=}" >"$d/$path"
    done
    local got
    got=$("$PY" "$RULES" "$d" 2>&1)
    if printf '%s' "$got" | grep -q "^FAIL $rule:"; then pass "tree_catches_$name"
    else fail "tree_catches_$name" "rule $rule not reported: $(printf '%s' "$got" | tr '\n' ' ')"; fi
}
broken twin_runtime twins_and_kernels_no_runtime_or_cli \
    'cpu/x.c=#include <CL/cl.h>'
broken twin_cli twins_and_kernels_no_runtime_or_cli \
    'cpu/x.c=#include "cli/cli.h"' 'host/cli/cli.h=int x;'
broken kernel_host kernels_include_only_kernels \
    'kernels/a.cl=#include "base/common.h"' 'host/base/common.h=int x;'
broken reference_fast_path reference_shares_only_fiber_math \
    'cpu/reference/r.c=#include "srbf_fast.h"' 'kernels/srbf_fast.h=int x;'
broken reference_plan reference_shares_only_fiber_math \
    'host/verify/reference/reference.c=#include "plan/frame.h"' 'host/plan/frame.h=int x;'
broken loader_pass loaders_know_no_passes \
    'host/scene/s.c=#include "passes/light/shadow.h"' 'host/passes/light/shadow.h=int x;'
broken pass_verify production_excludes_verify \
    'host/passes/view/v.h=#include "verify/checks/kernel_checks.h"' 'host/verify/checks/kernel_checks.h=int x;'
broken opencl_outside opencl_calls_only_in_cl_and_drivers \
    'host/plan/frame.c=void f(void) { clReleaseMemObject(0); }'
broken raw_kernel_arg kernel_args_through_cl_args \
    'host/passes/light/dodm_cl.c=void f(void) { clSetKernelArg(0, 0, 0, 0); }'
broken include_cycle no_include_cycles \
    'host/base/a.h=#include "base/b.h"' 'host/base/b.h=#include "base/a.h"'
broken folder_cycle no_folder_cycles \
    'host/plan/p.h=#include "passes/shade/s.h"' 'host/passes/shade/s.h=int x;' \
    'host/passes/shade/s.c=#include "plan/p.h"'
broken kernel_without_twin kernels_found_by_stem \
    'kernels/blur.cl=int x;' 'host/passes/view/blur_cl.c=int y;' 'test/passes/view/test_blur.c=int z;'
broken missing_include includes_resolve \
    'host/base/a.c=#include "base/none.h"'
broken test_misplaced tests_mirror_sources \
    'test/nowhere/test_x.c=int x;'
# A driver (*_cl.c) and the runtime may call OpenCL: the rule must not fire on them.
d="$TMP/tree_ok"; rm -rf "$d"; mkdir -p "$d/host/cl" "$d/host/passes/light" "$d/kernels" "$d/cpu"
echo 'void f(void) { clFinish(0); }' >"$d/host/cl/clrt.c"
echo 'void g(void) { clEnqueueNDRangeKernel(0, 0, 0, 0, 0, 0, 0, 0, 0); /* clFoo( in a comment */ }' >"$d/host/passes/light/dodm_cl.c"
echo 'void h(void) { clSetKernelArg(0, 0, 0, 0); }' >"$d/host/cl/cl_args.c"
echo 'const char *s = "clNotACall(";' >"$d/host/passes/light/shadow.c"
if "$PY" "$RULES" "$d" >/dev/null 2>&1; then pass tree_allows_drivers; else fail tree_allows_drivers "$("$PY" "$RULES" "$d" | grep FAIL)"; fi
exit 0
