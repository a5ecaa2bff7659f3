#!/usr/bin/env bash
# run.sh BUILD_DIR: `make test-farm` (docs/farm.md). Renders a small orbit of a tiny procedural
# scene once in a single process (the reference), then
#   1. checks the frame mapping of scripts/farm/orbit.sbatch without Slurm (dry run);
#   2. with GNU parallel (if installed): scripts/farm/orbit_parallel.sh, frames vs reference;
#   3. starts a REAL single-node Slurm on localhost in a private temp dir (own munge key and
#      socket, slurm.conf on free ports, no cgroups, no accounting), submits the orbit as an
#      array job (sbatch --array --wait), and compares every frame with the reference byte for
#      byte (`cmp`: the EXR writer stores only the required header attributes, no date, so equal
#      pixels mean equal files); each task builds its light passes once; a failing task must
#      fail the job; a rerun of one task with SL_FARM_SKIP_DONE=1 redoes only missing frames.
# The reference runs with every CPU's threads, the farm tasks with --threads 1 (the Slurm
# allocation), so the comparison also checks that frames do not depend on the thread count.
# Prints PASS/FAIL/SKIP lines like test/cli/lib.sh and timings; exits 1 if any check failed.
# Every daemon is killed and the temp dir removed on exit, also on failure or Ctrl-C
# (SL_FARM_KEEP=1 keeps the temp dir for debugging). Sizes: FARM_ORBIT (8 frames),
# FARM_PER_TASK (2 frames per task), FARM_STRANDS (200), FARM_WIDTH x FARM_HEIGHT (64 x 48).
set -u
BUILD=${1:-build}
N=${FARM_ORBIT:-8}
P=${FARM_PER_TASK:-2}
STRANDS=${FARM_STRANDS:-200}
W=${FARM_WIDTH:-64}
H=${FARM_HEIGHT:-48}
TASKS=$(((N + P - 1) / P))
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
SBATCH_SCRIPT="$ROOT/scripts/farm/orbit.sbatch"
t_start=$(date +%s.%N)
# a run inside a real Slurm job must not inherit that job's settings (task index, CPUs, config)
for v in $(compgen -e | grep -E '^(SLURM_|SBATCH_|SALLOC_|SRUN_)'); do unset "$v"; done

nfail=0
pass() { echo "PASS $1"; }
fail() { echo "FAIL $1: $2"; nfail=$((nfail + 1)); }
skip() { echo "SKIP $1: $2"; }
now() { date +%s.%N; }
secs() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.2f", b - a }'; }
rate() { awk -v n="$1" -v a="$2" -v b="$3" 'BEGIN { printf "%.2f", n / (b - a) }'; }

case $BUILD in /*) SL=$BUILD/strandlight ;; *) SL=$ROOT/$BUILD/strandlight ;; esac
if [ ! -x "$SL" ]; then
    fail farm_binary "$SL missing: build it first (make BUILD=$BUILD)"
    exit 1
fi

# a private temp dir; munged wants every directory of its socket path searchable by all and
# not writable by others, and a unix socket path must stay under 108 bytes: short, mode 755
T=$(mktemp -d "${TMPDIR:-/tmp}/sl-farm.XXXXXX") || { fail farm_tmpdir "mktemp failed"; exit 1; }
chmod 755 "$T"
pids=()       # daemons we started, in start order
sbatch_pid="" # the sbatch --wait client running now, if any
slurm_up=0
cleanup() {
    trap - EXIT INT TERM
    [ -n "$sbatch_pid" ] && kill "$sbatch_pid" 2>/dev/null
    if [ "$slurm_up" = 1 ]; then
        # cancel every job of this private cluster, so no slurmstepd or render outlives it
        local j
        for j in $(squeue -h -o %A 2>/dev/null | sort -u); do scancel "$j" 2>/dev/null; done
        for _ in $(seq 20); do
            [ -z "$(squeue -h 2>/dev/null)" ] && break
            sleep 0.25
        done
    fi
    local i
    for ((i = ${#pids[@]} - 1; i >= 0; i--)); do kill "${pids[i]}" 2>/dev/null; done
    for ((i = ${#pids[@]} - 1; i >= 0; i--)); do
        for _ in $(seq 20); do kill -0 "${pids[i]}" 2>/dev/null || break; sleep 0.25; done
        kill -9 "${pids[i]}" 2>/dev/null
        wait "${pids[i]}" 2>/dev/null
    done
    if [ "${SL_FARM_KEEP:-0}" = 1 ]; then echo "farm: kept $T"; else rm -rf "$T"; fi
}
trap cleanup EXIT
trap 'exit 130' INT TERM

# show the end of the daemons' logs and task outputs after a failure
dump_logs() {
    local f
    for f in "$T"/slurmctld.log "$T"/slurmd.log "$T"/munged.log "$T"/logs/*; do
        [ -f "$f" ] || continue
        echo "  --- ${f#"$T"/} (last lines)"
        tail -n 8 "$f" | sed 's/^/  | /'
    done
}

# --- the scene: 2 lobes from a file, tiny procedural hair, C path (every host has it) --------
mkdir -p "$T/scene" "$T/cache" "$T/logs"
cat > "$T/scene/lobes.json" <<'JSON'
{"lobes": [{"dir": [0, 1, 0], "lambda": 0.5, "rgb": [1, 0.9, 0.8]},
           {"dir": [0.6, 0, 0.8], "lambda": 0.8, "rgb": [0.4, 0.5, 0.6]}]}
JSON
cat > "$T/scene/s.json" <<JSON
{
  "hair": {"procedural": {"style": "wavy", "strands": $STRANDS, "points": 8, "seed": 2}, "radius": 0.04},
  "material": {"eta": 1.55, "sigma_a": [0.18, 0.32, 0.62]},
  "environment": {"lobes": "lobes.json"},
  "image": {"width": $W, "height": $H},
  "quality": {"multiple_scattering": "on"}
}
JSON
SCENE=$T/scene/s.json
# one cache for every process, as on a shared filesystem; filled once before any timing
export SL_CACHE_DIR=$T/cache
frame_name() { printf 'f_%04d.exr' "$1"; }

# compare_frames NAME DIR: DIR holds exactly frames 0..N-1, each identical to the reference
compare_frames() {
    local name=$1 dir=$2 f bad="" missing="" extra
    for ((f = 0; f < N; f++)); do
        if [ ! -f "$dir/$(frame_name "$f")" ]; then missing="$missing $f"
        elif ! cmp -s "$T/ref/$(frame_name "$f")" "$dir/$(frame_name "$f")"; then bad="$bad $f"; fi
    done
    extra=$(find "$dir" -mindepth 1 -maxdepth 1 ! -regex '.*/f_[0-9][0-9][0-9][0-9]\.exr' -printf '%f ')
    if [ -n "$missing" ]; then fail "$name" "frames missing:$missing"
    elif [ -n "$bad" ]; then fail "$name" "frames differ from the single-process run:$bad"
    elif [ -n "$extra" ]; then fail "$name" "unexpected files (temporaries?): $extra"
    else pass "$name"; fi
}

# --- 1. the task -> frame range mapping (no Slurm needed) --------------------------------
# orbit of 10, 4 per task: tasks 0..2 cover 0:4, 4:8, 8:10; task 3 has no frame. Expected
# ranges written out by hand from the rule "task T renders T*P .. min(T*P+P, N)-1".
dry() { env SL_FARM_DRY_RUN=1 SL=strandlight "$@" bash "$SBATCH_SCRIPT" s.json 10 4 o.exr 2>&1; }
got="$(dry SL_FARM_TASK_ID=0) | $(dry SL_FARM_TASK_ID=1) | $(dry SLURM_ARRAY_TASK_ID=2) | $(dry SL_FARM_TASK_ID=3)"
ok=1
for want in "--frames 0:4 " "--frames 4:8 " "--frames 8:10 " "task 3: no frames"; do
    [[ $got == *"$want"* ]] || ok=0
done
if [ "$ok" = 1 ]; then pass farm_task_ranges; else fail farm_task_ranges "$got"; fi
out=$(dry SLURM_ARRAY_TASK_ID=1 SLURM_CPUS_PER_TASK=3)
if [[ $out == *"--threads 3"* ]]; then pass farm_threads_follow_allocation
else fail farm_threads_follow_allocation "$out"; fi
out=$(env SL_FARM_DRY_RUN=1 SLURM_ARRAY_TASK_ID=0 SLURM_CPUS_PER_TASK=3 bash "$SBATCH_SCRIPT" \
    s.json 10 4 o.exr --threads 1 2>&1)
if [[ $out == *"--threads 1"* ]] && [[ $out != *"--threads 3"* ]]; then pass farm_threads_option_wins
else fail farm_threads_option_wins "$out"; fi
out=$(env SL_FARM_DRY_RUN=1 SLURM_ARRAY_TASK_ID=1 SLURM_ARRAY_TASK_MAX=1 bash "$SBATCH_SCRIPT" \
    s.json 10 4 o.exr 2>&1)
if [[ $out == *"frames 8..9 are in no task"* ]]; then pass farm_short_array_warns
else fail farm_short_array_warns "$out"; fi
bash "$SBATCH_SCRIPT" s.json 10 4 o.exr >/dev/null 2>&1 </dev/null
if [ $? -eq 1 ]; then pass farm_needs_task_index; else fail farm_needs_task_index "ran without a task index"; fi

# --- the reference: the whole orbit in one process ----------------------------------------
# warm-up: fills the SRBF table cache, so no timed run pays for building it
"$SL" render "$SCENE" --device c --orbit "$N" --frames 0:1 --exr "$T/warm/f.exr" \
    >/dev/null 2>"$T/logs/warm.err" || { fail farm_reference "warm-up render failed: $(tail -1 "$T/logs/warm.err")"; exit 1; }
t0=$(now)
if "$SL" render "$SCENE" --device c --orbit "$N" --exr "$T/ref/f.exr" >/dev/null 2>"$T/logs/ref.err"; then
    t1=$(now)
    echo "farm: single process: $N frames in $(secs "$t0" "$t1") s ($(rate "$N" "$t0" "$t1") frames/s)"
    pass farm_reference
else
    fail farm_reference "single-process render failed: $(tail -1 "$T/logs/ref.err")"
    exit 1
fi

# --- 2. GNU parallel -------------------------------------------------------------------------
if command -v parallel >/dev/null; then
    t0=$(now)
    if SL=$SL SL_FARM_JOBS=2 bash "$ROOT/scripts/farm/orbit_parallel.sh" "$SCENE" "$N" "$P" \
        "$T/par/f.exr" --device c --threads 1 >"$T/logs/parallel.out" 2>&1; then
        t1=$(now)
        echo "farm: GNU parallel, $TASKS tasks, 2 at a time: $N frames in $(secs "$t0" "$t1") s ($(rate "$N" "$t0" "$t1") frames/s)"
        compare_frames farm_parallel_frames_equal "$T/par"
    else
        fail farm_parallel_frames_equal "orbit_parallel.sh failed: $(tail -2 "$T/logs/parallel.out" | tr '\n' ' ')"
    fi
else
    skip farm_parallel_frames_equal "GNU parallel not installed (Debian package 'parallel')"
fi

# --- 3. a real single-node Slurm -------------------------------------------------------------
missing=""
for b in munged slurmctld slurmd sbatch sinfo squeue scancel scontrol munge; do
    command -v "$b" >/dev/null || missing="$missing $b"
done
if [ -n "$missing" ]; then
    skip farm_slurm "not installed:$missing (Debian: slurm-wlm munge, scripts/deps.sh)"
    [ "$nfail" -eq 0 ]
    exit
fi

# free TCP ports for slurmctld and slurmd (nothing answers on them), so a system Slurm or a
# second test run on this machine does not collide
port_free() { ! (exec 3<>"/dev/tcp/127.0.0.1/$1") 2>/dev/null; }
pick_port() {
    local p
    for _ in $(seq 50); do
        p=$((20000 + RANDOM % 30000))
        if port_free "$p" && [ "$p" != "${1:-}" ]; then echo "$p"; return 0; fi
    done
    return 1
}
if ! ctld_port=$(pick_port) || ! d_port=$(pick_port "$ctld_port"); then
    fail farm_slurm_start "no free TCP port found"
    exit 1
fi

# munge: a private key and socket, in the foreground (-F) so that its pid is ours to kill
if command -v mungekey >/dev/null; then
    mungekey --create --keyfile="$T/munge.key" 2>"$T/logs/mungekey.err"
else
    dd if=/dev/urandom of="$T/munge.key" bs=1024 count=1 2>/dev/null
fi
chmod 600 "$T/munge.key"
munged -F --socket="$T/munge.sock" --key-file="$T/munge.key" --pid-file="$T/munged.pid" \
    --log-file="$T/munged.log" --seed-file="$T/munged.seed" >"$T/logs/munged.out" 2>&1 &
pids+=($!)
for _ in $(seq 40); do munge -S "$T/munge.sock" -n >/dev/null 2>&1 && break; sleep 0.25; done
if ! munge -S "$T/munge.sock" -n >/dev/null 2>&1; then
    fail farm_slurm_start "munged did not start: $(tail -1 "$T/munged.log" 2>/dev/null)"
    exit 1
fi

# slurm.conf: the node is this machine as `slurmd -C` sees it, named localhost (slurmd -N)
node=$(slurmd -C 2>/dev/null | head -1 | tr ' ' '\n' |
    grep -E '^(CPUs|Boards|SocketsPerBoard|CoresPerSocket|ThreadsPerCore|RealMemory)=' | tr '\n' ' ')
[ -n "$node" ] || node="CPUs=$(nproc)"
user=$(id -un)
mkdir -p "$T/state" "$T/spool"
cat > "$T/slurm.conf" <<EOF
# generated by test/farm/run.sh: a throw-away single-node cluster
ClusterName=slfarm
SlurmctldHost=localhost
SlurmctldPort=$ctld_port
SlurmdPort=$d_port
SlurmUser=$user
SlurmdUser=$user
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$T/munge.sock
StateSaveLocation=$T/state
SlurmdSpoolDir=$T/spool
SlurmctldPidFile=$T/slurmctld.pid
SlurmdPidFile=$T/slurmd.pid
SlurmctldLogFile=$T/slurmctld.log
SlurmdLogFile=$T/slurmd.log
MailProg=/bin/true
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
SchedulerType=sched/builtin
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
# sbatch --wait sleeps 2 s, then 4x longer while that sleep < MinJobAge / 2 (sbatch.c
# _job_wait): 4 keeps it at 2 s (measured: array job 6.1 s instead of 10.2 s with the default
# 300). A finished job is forgotten 4 s after its end, 2 s after sbatch's next poll at the latest.
MinJobAge=4
NodeName=localhost NodeAddr=127.0.0.1 $node State=UNKNOWN
PartitionName=farm Nodes=localhost Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF=$T/slurm.conf
t_daemons=$(now)
slurmctld -D -f "$SLURM_CONF" >"$T/logs/slurmctld.out" 2>&1 &
pids+=($!)
slurmd -D -f "$SLURM_CONF" -N localhost >"$T/logs/slurmd.out" 2>&1 &
pids+=($!)
state=""
for _ in $(seq 120); do
    state=$(sinfo -h -n localhost -o %t 2>/dev/null)
    [ "$state" = idle ] && break
    sleep 0.25
done
slurm_up=1
if [ "$state" = idle ]; then
    pass farm_slurm_start
    echo "farm: Slurm up in $(secs "$t_daemons" "$(now)") s (ports $ctld_port, $d_port; node $node)"
else
    fail farm_slurm_start "node not idle after 30 s (state '$state')"
    dump_logs
    exit 1
fi

# submit NAME ARRAY ARGS...: sbatch --wait the orbit script, returns sbatch's exit status. It
# runs in the background and is waited for, so that Ctrl-C / TERM reach the cleanup at once.
submit() {
    local name=$1 array=$2 rc
    shift 2
    timeout 120 sbatch --wait --array="$array" --cpus-per-task=1 -D "$T" -J "$name" \
        -o "$T/logs/${name}_%a.out" "$SBATCH_SCRIPT" "$@" >"$T/logs/$name.sbatch" 2>&1 &
    sbatch_pid=$!
    wait "$sbatch_pid"
    rc=$?
    sbatch_pid=""
    return $rc
}

# the array job: TASKS tasks of P consecutive frames; --explain shows each task's passes
t0=$(now)
if SL=$SL submit orbit "0-$((TASKS - 1))" "$SCENE" "$N" "$P" "$T/farm/f.exr" --device c --explain; then
    t1=$(now)
    echo "farm: Slurm array job, $TASKS tasks of $P frames, 1 CPU each: $N frames in $(secs "$t0" "$t1") s ($(rate "$N" "$t0" "$t1") frames/s, sbatch --wait polling included)"
    pass farm_slurm_array_job
    compare_frames farm_slurm_frames_equal "$T/farm"
    # light-pass reuse within a task: the deep opacity maps are built once per task
    bad=""
    for ((t = 0; t < TASKS; t++)); do
        nf=$(((t + 1) * P < N ? P : N - t * P))
        runs=$(grep -c '^light  *run' "$T/logs/orbit_$t.out")
        cached=$(grep -c '^light  *cached' "$T/logs/orbit_$t.out")
        [ "$runs" = 1 ] && [ "$cached" = $((nf - 1)) ] || bad="$bad task$t:run=$runs,cached=$cached"
    done
    if [ -z "$bad" ]; then pass farm_slurm_task_reuses_light; else fail farm_slurm_task_reuses_light "$bad"; fi
else
    fail farm_slurm_array_job "sbatch exit $?: $(tail -2 "$T/logs/orbit.sbatch" | tr '\n' ' ')"
    dump_logs
fi

# a task that fails (missing scene) fails the array job: sbatch --wait exits non-zero
if SL=$SL submit broken 0-1 "$T/scene/missing.json" "$N" "$P" "$T/broken/f.exr" --device c; then
    fail farm_slurm_failure_reported "sbatch --wait exited 0 for failing tasks"
elif grep -q 'missing.json' "$T/logs/broken_0.out" && [ ! -e "$T/broken" ]; then
    pass farm_slurm_failure_reported
else
    fail farm_slurm_failure_reported "task log: $(tail -1 "$T/logs/broken_0.out" 2>&1)"
fi

# rerun task 0 after losing its frame 1: frame 0 (kept, its mtime must not change) is skipped,
# the task renders from frame 1 to the end of its range
if [ -f "$T/farm/$(frame_name 1)" ] && [ "$N" -ge 2 ] && [ "$P" -ge 2 ]; then
    rm -f "$T/farm/$(frame_name 1)"
    touch -d '2000-01-01' "$T/farm/$(frame_name 0)"
    if SL=$SL SL_FARM_SKIP_DONE=1 submit rerun 0 "$SCENE" "$N" "$P" "$T/farm/f.exr" --device c &&
        grep -q "frames 1\.\.$(((P < N ? P : N) - 1)) of" "$T/logs/rerun_0.out" &&
        [ "$(stat -c %Y "$T/farm/$(frame_name 0)")" = "$(date -d '2000-01-01' +%s)" ]; then
        compare_frames farm_slurm_rerun_fills_gap "$T/farm"
    else
        fail farm_slurm_rerun_fills_gap "$(tail -2 "$T/logs/rerun_0.out" 2>&1 | tr '\n' ' ')"
    fi
else
    skip farm_slurm_rerun_fills_gap "needs an orbit of 2+ frames with 2+ per task"
fi

echo "farm: done in $(secs "$t_start" "$(now)") s"
[ "$nfail" -eq 0 ]
