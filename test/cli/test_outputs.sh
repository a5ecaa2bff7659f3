# test_outputs.sh: safe outputs (issue 21, docs/robustness.md "Outputs"): an output path that is
# a FIFO, a device, a symbolic link, one of the run's own inputs (scene, map, lobes) or the
# other output of the same run is refused with one line and exit 1, and nothing is touched;
# `report -o DIR` never deletes a directory's files it did not write (only a directory holding
# its manifest, or an empty one, is replaced) and swaps it in atomically; a render's EXR and PNG
# change as one set; temporaries have unpredictable names, refuse an existing file, and are gone
# after a normal run and after SIGTERM.
. test/cli/lib.sh
D="$TMP/outputs"
rm -rf "$D"
mkdir -p "$D"
cat > "$D/lobes.json" <<'JSON'
{"lobes": [{"dir": [0, 1, 0], "lambda": 0.5, "rgb": [1, 0.9, 0.8]}]}
JSON
cat > "$D/s.json" <<'JSON'
{"hair": {"procedural": {"style": "wavy", "strands": 30, "points": 8, "seed": 1}, "radius": 0.05},
 "material": {"model": "chiang", "melanin": 0.5},
 "environment": {"lobes": "lobes.json"}, "camera": {"fov_deg": 30},
 "image": {"width": 24, "height": 16}, "quality": {"multiple_scattering": "off"}}
JSON
cp "$D/s.json" "$D/s.orig"
cp "$D/lobes.json" "$D/lobes.orig"
r() { "$SL" render "$D/s.json" --device c --quiet "$@"; }

mkfifo "$D/fifo"
expect_error out_fifo_refused "fifo: exists and is not a regular file" r --exr "$D/fifo"
if [ -p "$D/fifo" ]; then pass out_fifo_kept; else fail out_fifo_kept "the FIFO was replaced"; fi
expect_error out_device_refused "/dev/null: exists and is not a regular file" r --exr /dev/null
if [ -c /dev/null ]; then pass out_device_kept; else fail out_device_kept "/dev/null is no device"; fi
echo keep > "$D/target"
ln -s target "$D/link"
expect_error out_symlink_refused "link: is a symbolic link" r --exr "$D/link"
if [ -L "$D/link" ] && [ "$(cat "$D/target")" = keep ]; then pass out_symlink_kept
else fail out_symlink_kept "link or its target changed"; fi
expect_error out_is_scene "s.json: is one of this run's inputs" r --exr "$D/s.json"
expect_error out_png_is_lobes "lobes.json: is one of this run's inputs" r --exr "$D/a.exr" --png "$D/lobes.json"
# the same file under another name (a hard link) is still the input
ln "$D/s.json" "$D/hard.json"
expect_error out_is_scene_hardlink "hard.json: is one of this run's inputs" r --exr "$D/hard.json"
expect_error out_png_is_exr "the same file as the EXR output" r --exr "$D/a.exr" --png "$D/a.exr"
expect_error out_reference_is_scene "s.json: is one of this run's inputs" \
    "$SL" reference "$D/s.json" --path --spp 1 -o "$D/s.json"
if cmp -s "$D/s.json" "$D/s.orig" && cmp -s "$D/lobes.json" "$D/lobes.orig"; then pass out_inputs_intact
else fail out_inputs_intact "an input was changed"; fi
if [ ! -e "$D/a.exr" ]; then pass out_refused_writes_nothing; else fail out_refused_writes_nothing "a.exr exists"; fi

# a normal run: the outputs, 0644 under umask 022, no temporaries left
( umask 022; r --exr "$D/ok.exr" --png "$D/ok.png" ) >/dev/null 2>&1
m=$(stat -c %a "$D/ok.exr" 2>/dev/null)
if [ -s "$D/ok.exr" ] && [ -s "$D/ok.png" ] && [ "$m" = 644 ]; then pass out_normal_run
else fail out_normal_run "mode '$m'"; fi
# killed at some point of a longer run (several frames): no temporary left, whatever the moment
for t in 0.3 0.8 1.5; do
    timeout -s TERM "$t" "$SL" render "$D/s.json" --device c --quiet --orbit 40 --exr "$D/orbit.exr" >/dev/null 2>&1
done
left=$(ls -a "$D" | grep -c '\.tmp' || true)
if [ "$left" -eq 0 ]; then pass out_sigterm_no_temporaries
else fail out_sigterm_no_temporaries "$(ls -a "$D" | grep '\.tmp')"; fi

# EXR + PNG are one set: a signal at any step of the output (SL_KILL_AT=k: the k-th kill point,
# SL_KILL_SIGNAL: which signal) leaves both old or both new, never a new EXR beside an old PNG;
# SIGTERM is held off between the two renames, so a TERM there lands after both
pair_state() { # old / new / mixed
    e=$(head -c 3 "$D/pa.exr"); p=$(head -c 3 "$D/pa.png")
    if [ "$e" = old ] && [ "$p" = old ]; then echo old
    elif [ "$e" != old ] && [ "$p" != old ] && [ -s "$D/pa.exr" ] && [ -s "$D/pa.png" ]; then echo new
    else echo mixed; fi
}
npoints=$(SL_KILL_POINTS=1 r --exr "$D/pa.exr" --png "$D/pa.png" 2>&1 | grep -c 'kill point')
if [ "$npoints" -eq 3 ]; then pass out_pair_kill_points; else fail out_pair_kill_points "$npoints points"; fi
for k in 1 2 3; do
    for sig in 15 2 1; do
        echo old > "$D/pa.exr"; echo old > "$D/pa.png"
        SL_KILL_AT=$k SL_KILL_SIGNAL=$sig r --exr "$D/pa.exr" --png "$D/pa.png" >/dev/null 2>&1; rc=$?
        st=$(pair_state)
        want=old; [ "$k" -eq 3 ] && want=new # the signal lands after the second rename
        left=$(ls -a "$D" | grep -c '^pa\..*\.tmp' || true)
        if [ "$rc" -eq $((128 + sig)) ] && [ "$st" = "$want" ] && [ "$left" -eq 0 ]; then
            pass "out_pair_signal_${sig}_at_$k"
        else fail "out_pair_signal_${sig}_at_$k" "rc=$rc state=$st (want $want) temporaries=$left"; fi
    done
    # SIGKILL cannot be held off: at points 1 and 2 the old pair stays whole (the temporaries
    # stay too: no handler runs); point 3 is the documented window (a new EXR, the old PNG)
    if [ "$k" -lt 3 ]; then
        echo old > "$D/pa.exr"; echo old > "$D/pa.png"
        SL_KILL_AT=$k r --exr "$D/pa.exr" --png "$D/pa.png" >/dev/null 2>&1
        st=$(pair_state)
        if [ "$st" = old ]; then pass "out_pair_sigkill_at_$k"; else fail "out_pair_sigkill_at_$k" "$st"; fi
        rm -f "$D"/pa.*.tmp*
    fi
done

sed "s#\"lobes\": \"lobes.json\"#\"file\": \"$PWD/data/env/city_256.hdr\"#" "$D/s.json" > "$D/rs.json"
# report -o: a directory with a user's file is refused, the file kept; a fresh directory gets the
# manifest, and a second report replaces it
mkdir -p "$D/mine"
echo "my notes" > "$D/mine/results.csv"
expect_error report_refuses_user_dir "mine: exists and is not a report directory" \
    "$SL" report "$D/rs.json" --tiny --threads 1 -o "$D/mine"
if [ "$(cat "$D/mine/results.csv")" = "my notes" ]; then pass report_user_file_kept
else fail report_user_file_kept "results.csv changed"; fi
if [ -z "${SL_OUTPUTS_SKIP_REPORT:-}" ]; then
    "$SL" report "$D/rs.json" --tiny --threads 1 -o "$D/rep" >/dev/null 2>&1
    "$SL" report "$D/rs.json" --tiny --threads 1 -o "$D/rep" >/dev/null 2>&1; rc=$?
    if [ "$rc" -eq 0 ] && [ -f "$D/rep/.strandlight-report" ] && [ -s "$D/rep/results.csv" ] &&
       [ "$(ls -d "$D"/rep.* 2>/dev/null | wc -l)" -eq 0 ] && [ ! -L "$D/rep" ]; then
        pass report_replaces_its_own
    else fail report_replaces_its_own "rc=$rc: $(ls -a "$D/rep" "$D" 2>&1 | tr '\n' ' ')"; fi
    # the swap is one RENAME_EXCHANGE: SIGKILLed just before or just after it (SL_KILL_AT: the
    # k-th kill point), DIR holds a whole report, every file its manifest lists (the swap at every
    # point, and the link fallback, are unit tests: report_dir_kill_*)
    whole() { [ -f "$1/.strandlight-report" ] && [ -s "$1/results.csv" ] &&
              for f in $(sed -n 's/^file //p' "$1/.strandlight-report"); do [ -s "$1/$f" ] || return 1; done; }
    rr() { "$SL" report "$D/rs.json" --tiny --threads 1 --device none -o "$D/rep" "$@"; }
    pts=$(SL_KILL_POINTS=1 rr 2>&1 | grep 'kill point')
    for what in "before the exchange" "exchanged"; do
        k=$(printf '%s\n' "$pts" | grep ": report: $what\$" | sed 's/.*kill point \([0-9]*\):.*/\1/')
        SL_KILL_AT=${k:-999} rr >/dev/null 2>&1; rc=$?
        name=report_killed_$(echo "$what" | tr ' ' _)
        if [ -n "$k" ] && [ "$rc" -eq 137 ] && [ -d "$D/rep" ] && whole "$D/rep"; then pass "$name"
        else fail "$name" "k=$k rc=$rc: $(ls -a "$D/rep" 2>&1 | tr '\n' ' ')"; fi
    done
    rm -rf "$D"/rep.report-* # the old report a kill after the exchange leaves beside DIR
    # where the filesystem has no RENAME_EXCHANGE: DIR becomes a link to a versioned directory,
    # and each later swap is one rename of a link
    SL_NO_RENAME_EXCHANGE=1 rr >/dev/null 2>&1; rc1=$?
    SL_NO_RENAME_EXCHANGE=1 rr >/dev/null 2>&1; rc2=$?
    n=$(ls -d "$D"/rep.* 2>/dev/null | wc -l)
    if [ "$rc1" -eq 0 ] && [ "$rc2" -eq 0 ] && [ -L "$D/rep" ] && whole "$D/rep" && [ "$n" -eq 1 ]; then
        pass report_link_fallback
    else fail report_link_fallback "rc=$rc1,$rc2, $n beside: $(ls -la "$D" | tr '\n' ' ')"; fi
fi

# the disk cache's directory: created 0700; one others can write, or another user's, is not used
# (one warning, the render still succeeds, nothing written there)
SL_CACHE_DIR="$D/cache/new" r --exr "$D/c1.exr" >/dev/null 2>&1
m=$(stat -c %a "$D/cache/new" 2>/dev/null)
if [ "$m" = 700 ] && [ -n "$(ls "$D/cache/new")" ]; then pass cache_dir_created_private
else fail cache_dir_created_private "mode '$m', entries: $(ls "$D/cache/new" 2>&1 | head -3)"; fi
mkdir -p "$D/cache/open"; chmod 777 "$D/cache/open"
out=$(SL_CACHE_DIR="$D/cache/open" r --exr "$D/c2.exr" 2>&1); rc=$?
if [ "$rc" -eq 0 ] && printf '%s' "$out" | grep -q "is writable by other users: not used" &&
   [ -z "$(ls "$D/cache/open")" ] && [ -s "$D/c2.exr" ]; then pass cache_dir_open_refused
else fail cache_dir_open_refused "rc=$rc: $out"; fi
if [ "$(id -u)" = 0 ] && id nobody >/dev/null 2>&1; then
    mkdir -p "$D/cache/theirs"; chown nobody "$D/cache/theirs"
    out=$(SL_CACHE_DIR="$D/cache/theirs" r --exr "$D/c3.exr" 2>&1); rc=$?
    if [ "$rc" -eq 0 ] && printf '%s' "$out" | grep -q "belongs to another user: not used" &&
       [ -z "$(ls "$D/cache/theirs")" ]; then pass cache_dir_other_owner_refused
    else fail cache_dir_other_owner_refused "rc=$rc: $out"; fi
else
    skip cache_dir_other_owner_refused "not root: cannot give a directory to another user"
fi
