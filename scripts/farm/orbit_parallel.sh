#!/usr/bin/env bash
# orbit_parallel.sh: renders a `strandlight render --orbit N` sequence with GNU parallel, on this
# machine or on several over ssh (docs/farm.md). It runs the very task script of the Slurm
# array job (scripts/farm/orbit.sbatch) once per task index, so a task renders the same P
# consecutive frames under Slurm and under parallel, and the frames equal a single-process run.
#
#   scripts/farm/orbit_parallel.sh SCENE.json N P OUT.exr [render options, e.g. --device c]
#
# Environment:
#   SL                 the strandlight binary (default: `strandlight` on PATH)
#   SL_FARM_JOBS       tasks run at once per machine (default 1: one process uses every CPU;
#                      with J > 1 give --threads C so that J x C <= CPUs)
#   SL_FARM_SSHLOGIN   comma-separated parallel --sshlogin list, e.g. "4/node1,4/node2,:"
#                      (":" is this machine); every machine must see the same absolute paths
#                      (shared filesystem) and run the same strandlight build
#   SL_CACHE_DIR, SL_FARM_SKIP_DONE are passed on to every task.
# Exits non-zero when any task fails (parallel --halt soon,fail=1: running tasks finish, no
# new one starts); the frames already written are complete files (atomic output).
set -euo pipefail

die() { echo "orbit_parallel.sh: $*" >&2; exit 1; }
[ $# -ge 4 ] || die "usage: orbit_parallel.sh SCENE.json N FRAMES_PER_TASK OUT.exr [render options]"
command -v parallel >/dev/null || die "GNU parallel is not installed (Debian: apt-get install parallel)"
scene=$1 n=$2 per=$3 out=$4
shift 4
is_count() { [[ $1 =~ ^[0-9]+$ ]] && [ "$1" -ge 1 ]; }
is_count "$n" || die "N: expected a frame count >= 1, got '$n'"
is_count "$per" || die "FRAMES_PER_TASK: expected a count >= 1, got '$per'"

# absolute paths: a remote task starts in its home directory
abs() { case $1 in /*) printf '%s' "$1" ;; *) printf '%s/%s' "$PWD" "$1" ;; esac; }
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
sl=${SL:-$(command -v strandlight || true)}
[ -n "$sl" ] || die "no strandlight binary: set SL=/path/to/strandlight"
envs=(SL="$(abs "$sl")" SL_FARM_SKIP_DONE="${SL_FARM_SKIP_DONE:-0}")
[ -n "${SL_CACHE_DIR:-}" ] && envs+=(SL_CACHE_DIR="$(abs "$SL_CACHE_DIR")")

opts=(-q --halt "soon,fail=1" --line-buffer --tag -j "${SL_FARM_JOBS:-1}")
[ -n "${SL_FARM_SSHLOGIN:-}" ] && opts+=(--sshlogin "$SL_FARM_SSHLOGIN")
tasks=$(((n + per - 1) / per))
# -q quotes every word, so paths with spaces survive the shell on each machine
seq 0 $((tasks - 1)) |
    parallel "${opts[@]}" env SL_FARM_TASK_ID={} "${envs[@]}" \
        bash "$here/orbit.sbatch" "$(abs "$scene")" "$n" "$per" "$(abs "$out")" "$@"
