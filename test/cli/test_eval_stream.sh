# test_eval_stream.sh: `strandlight eval` streams its rows (issue 21; docs/eval.md "Streaming",
# docs/robustness.md sec. 5): a 2M-row input, generated here by awk and piped in (never stored),
# runs under an address-space cap far below what holding the whole table in memory needs, gives
# every row in order, and a bad row in the last chunk still gives the one-line error and no output
# file. Chunking itself must not change a byte: outputs with 7-row chunks equal those of one
# chunk.
#
# The cap: the binary with its libraries maps ~62 MB of address space on a one-row input
# (measured: `prlimit --as=60M` fails to start it, 64M runs it); streaming adds about a chunk's
# worth (65536 rows: text, fields, values, formatted output, ~30 MB). 300 MB leaves ~200 MB of
# margin over that, and is well under the ~1 GB that the 2M rows take held at once (a check below
# runs them as a single chunk under the same cap and expects it to fail, so the cap does bite).
. test/cli/lib.sh
D="$TMP/eval_stream"
rm -rf "$D"
mkdir -p "$D"
CAP=$((300 * 1024 * 1024))
N=2000000
if ! command -v prlimit >/dev/null 2>&1; then skip eval_stream "no prlimit"; exit 0; fi
# Under AddressSanitizer (make asan) the binary reserves terabytes of shadow address space, so
# no address-space cap can hold it: the rows are checked without the cap, and the two checks
# about the cap itself are skipped.
CAPPED=(prlimit --as=$CAP)
ASAN=0
if ldd "$SL" 2>/dev/null | grep -q libasan; then CAPPED=(); ASAN=1; fi

# rows N: deon-mp's v,theta_i,theta_o for rows 0..N-1 (the cheapest quantity: three inputs, two
# outputs, a closed form); row i is a function of i alone, so any row can be made again.
rows() { awk -v n="$1" -v f="${2:-0}" 'BEGIN { print "v,theta_i,theta_o,id"
    for (i = f; i < n; i++) printf "%.4f,%.4f,%.4f,%d\n", 0.01 + (i % 97) / 100, (i % 151) / 100 - 0.75, (i % 89) / 60 - 0.7, i }'; }

# the cap leaves the binary room to start and run a tiny input
if [ $ASAN = 1 ]; then skip eval_stream_cap_starts "AddressSanitizer build: no address-space cap"
elif printf 'v,theta_i,theta_o\n0.5,0.1,0.2\n' | prlimit --as=$CAP "$SL" eval deon-mp > /dev/null 2>"$D/err"; then
    pass eval_stream_cap_starts
else fail eval_stream_cap_starts "$(head -2 "$D/err")"; fi

# 2M rows under the cap, written with --output: exit 0, one line per row plus the header
rows $N | "${CAPPED[@]}" "$SL" eval deon-mp -o "$D/big.csv" 2>"$D/err"
rc=$?
lines=$(wc -l < "$D/big.csv" 2>/dev/null || echo 0)
if [ "$rc" -eq 0 ] && [ "$lines" -eq $((N + 1)) ]; then pass eval_stream_2M_rows_under_cap
else fail eval_stream_2M_rows_under_cap "exit $rc, $lines lines (want $((N + 1))): $(head -2 "$D/err")"; fi
# every row in order (the id column counts 0..N-1), and the last row's values are what a run on
# that row alone gives (nothing shifted between chunks)
if awk -F, 'NR > 1 && $4 != NR - 2 { bad = 1; exit } END { exit bad }' "$D/big.csv"; then
    pass eval_stream_rows_in_order
else fail eval_stream_rows_in_order "the id column is not 0..N-1 in order"; fi
last=$(rows $N $((N - 1)) | "$SL" eval deon-mp | tail -1)
if [ "$(tail -1 "$D/big.csv")" = "$last" ]; then pass eval_stream_last_row
else fail eval_stream_last_row "got '$(tail -1 "$D/big.csv")', alone '$last'"; fi
rm -f "$D/big.csv"

# the same rows as one chunk (the whole table in memory, as eval did before streaming) exceed the
# cap: the check above would fail without streaming
if [ $ASAN = 1 ]; then skip eval_stream_cap_bites "AddressSanitizer build: no address-space cap"
elif rows $N | SL_EVAL_CHUNK_ROWS=$N prlimit --as=$CAP "$SL" eval deon-mp -o "$D/one.csv" 2>"$D/err"; then
    fail eval_stream_cap_bites "a single 2M-row chunk ran under the cap: the cap proves nothing"
elif grep -q 'out of memory' "$D/err" && [ ! -e "$D/one.csv" ]; then pass eval_stream_cap_bites
else fail eval_stream_cap_bites "$(head -2 "$D/err")"; fi

# a bad row on the last line of 200 000 (the 4th chunk of 65536 rows, the first three already
# evaluated and written to the temporary): one line naming the line, exit 1, no output file, no
# temporary left; on stdout: nothing
M=200000
bad() { rows $M; echo "0.5,0.1,x,$M"; }
bad | "${CAPPED[@]}" "$SL" eval deon-mp -o "$D/bad.csv" 2>"$D/err"
rc=$?
want="<stdin>:$((M + 2)): theta_o: 'x' is not a number"
if [ "$rc" -eq 1 ] && [ "$(grep -c '' "$D/err")" -eq 1 ] && grep -qF "$want" "$D/err" && [ ! -e "$D/bad.csv" ]; then
    pass eval_stream_bad_last_chunk_no_file
else fail eval_stream_bad_last_chunk_no_file "exit $rc, stderr '$(head -2 "$D/err")', file: $(ls "$D")"; fi
no_leftovers eval_stream_bad_last_chunk_no_temporary "$D"
out=$(bad | "$SL" eval deon-mp 2>/dev/null); rc=$?
if [ "$rc" -eq 1 ] && [ -z "$out" ]; then pass eval_stream_bad_last_chunk_stdout_empty
else fail eval_stream_bad_last_chunk_stdout_empty "exit $rc, ${#out} bytes on stdout"; fi

# -o FILE: the same bytes as stdout; refused before any work over an input or a non-file
printf 'theta_i,phi_i,theta_o,phi_o\n0.1,0.2,0.3,0.4\n' > "$D/one.csv"
printf '{"sigma_a": [0.2, 0.4, 0.8]}\n' > "$D/rgb.json"
"$SL" eval scatter -o "$D/sub/o.csv" < "$D/one.csv" 2>"$D/err"
if [ "$("$SL" eval scatter < "$D/one.csv")" = "$(cat "$D/sub/o.csv" 2>/dev/null)" ]; then pass eval_stream_output_file
else fail eval_stream_output_file "-o gave '$(cat "$D/sub/o.csv" 2>/dev/null)': $(cat "$D/err")"; fi
expect_error eval_stream_output_is_material "is one of this run's inputs" "$SL" eval scatter -o "$D/rgb.json" --material "$D/rgb.json" < "$D/one.csv"
expect_error eval_stream_output_not_a_file "is not a regular file" "$SL" eval scatter -o /dev/null < "$D/one.csv"

# chunking changes no byte: 7-row chunks against one chunk, for quantities whose backends keep
# state between chunks (srbf's tables, Ren's table) and an rgb material (channel-major values)
printf 'theta_o,phi_o,theta_j,phi_j,lambda\n' > "$D/srbf.csv"
awk 'BEGIN { for (i = 0; i < 40; i++) printf "%.3f,%.3f,%.3f,%.3f,%.2f\n", (i % 7) / 5 - 0.6, (i % 11) / 4 - 1.2, (i % 5) / 4 - 0.5, (i % 13) / 5 - 1.1, 1 + i % 9 }' >> "$D/srbf.csv"
printf 'theta_i,phi_i,theta_o,phi_o,tag\n' > "$D/scatter.csv"
awk 'BEGIN { for (i = 0; i < 40; i++) printf "%.3f,%.3f,%.3f,%.3f, t%d \n", (i % 7) / 5 - 0.6, (i % 11) / 4 - 1.2, (i % 5) / 4 - 0.5, (i % 13) / 5 - 1.1, i }' >> "$D/scatter.csv"
chunks_same() {
    local name=$1 in=$2; shift 2
    local a b
    a=$(SL_EVAL_CHUNK_ROWS=7 "$SL" eval "$@" < "$in" 2>&1) && b=$(SL_EVAL_CHUNK_ROWS=1000 "$SL" eval "$@" < "$in" 2>&1)
    if [ $? -eq 0 ] && [ "$a" = "$b" ] && [ "$(printf '%s\n' "$a" | wc -l)" -eq 41 ]; then pass "$name"
    else fail "$name" "7-row chunks and one chunk differ (or failed): $(printf '%s' "$a" | tail -1)"; fi
}
chunks_same eval_stream_chunks_scatter_rgb "$D/scatter.csv" scatter --material "$D/rgb.json"
chunks_same eval_stream_chunks_scatter_reference "$D/scatter.csv" scatter --backend reference
chunks_same eval_stream_chunks_srbf_fast "$D/srbf.csv" srbf --material "$D/rgb.json"
chunks_same eval_stream_chunks_srbf_table "$D/srbf.csv" srbf --method table
if have_cl; then
    chunks_same eval_stream_chunks_scatter_opencl "$D/scatter.csv" scatter --material "$D/rgb.json" --device "$SL_CL_DEVICE"
else cl_skip eval_stream_chunks_scatter_opencl "no OpenCL device"; fi

# the scene quantities keep the scene, and their light pass / march, across chunks; a lobe first
# used in a later chunk rebuilds them for every lobe used so far, in order of first use, which
# must give the bytes of one pass (the march's random streams are keyed by that order); the
# reference's Monte Carlo seed is the row's index in the whole input
if [ -x /usr/bin/python3 ]; then PY=/usr/bin/python3; else PY=python3; fi
if command -v "$PY" >/dev/null 2>&1; then
    "$PY" test/cli/slab_hair.py "$D/slab.hair" 200 0.005
    printf '{"lobes": [{"dir": [0, 0, 1], "lambda": 0.05, "rgb": [1, 1, 1]}, {"dir": [0, 0.6, 0.8], "lambda": 0.05, "rgb": [1, 1, 1]}]}\n' > "$D/lobes.json"
    printf '{"hair": {"file": "slab.hair"}, "environment": {"lobes": "lobes.json"}, "material": {"sigma_a": [0.2, 0.4, 0.8]}, "quality": {"voxels": 16, "shadow_size": 64}}\n' > "$D/scene.json"
    { echo "x,y,z,lobe"; awk 'BEGIN { for (i = 0; i < 40; i++) printf "%.3f,%.3f,%.3f,%d\n", (i % 7) / 5 - 0.6, (i % 11) / 8 - 0.6, -(i % 5) / 6, (i >= 20 ? 1 : 0) }'; } > "$D/pts.csv"
    # 40 rows, lobe 0 then lobe 1 from row 20: with 7-row chunks lobe 1 first comes in chunk 3
    chunks_same eval_stream_chunks_transmittance_c "$D/pts.csv" transmittance --scene "$D/scene.json"
    chunks_same eval_stream_chunks_transmittance_reference "$D/pts.csv" transmittance --scene "$D/scene.json" --backend reference
    chunks_same eval_stream_chunks_forward_c "$D/pts.csv" forward-transmittance --scene "$D/scene.json"
    if have_cl; then
        chunks_same eval_stream_chunks_forward_opencl "$D/pts.csv" forward-transmittance --scene "$D/scene.json" --device "$SL_CL_DEVICE"
    else cl_skip eval_stream_chunks_forward_opencl "no OpenCL device"; fi
else skip eval_stream_chunks_scene "no python3"; fi
rm -rf "$D"
