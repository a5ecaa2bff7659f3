# test_layers.sh: the layering rules of host/ (scripts/check_layers.py): no header include
# cycles, no host/verify includes in passes/plan/cl, OpenCL calls only in host/cl and *_cl.c,
# kernel arguments only through cl/cl_args.h.
. test/cli/lib.sh
if ! command -v python3 >/dev/null 2>&1; then
    skip host_layers "no python3"
elif out=$(python3 scripts/check_layers.py 2>&1); then
    pass host_layers
else
    fail host_layers "$(printf '%s' "$out" | head -5 | tr '\n' ';')"
fi
