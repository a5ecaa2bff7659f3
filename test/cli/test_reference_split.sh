# test_reference_split.sh: the reference's light split and its convergence record (issue 10,
# docs/reference.md). On a tiny scene (32x24, 200 procedural strands, a 16x8 two-band sky cut
# into 16 lights, aa 4):
#  - light split is unbiased: the mean image brightness with the split (each of the 16 rays of a
#    pixel shades 1 of the 16 lights, weight 16) matches the image where every ray shades every
#    light, over 8 seeds (bound below); with the same seed both have the same camera rays
#    (same coverage);
#  - the split changes the image (the option does something) and is deterministic for any
#    thread count (identical EXR bytes);
#  - the JSON records light_split, the 2N render's other seed (seed_2n = seed + 1), mean_rgb and
#    coverage, and --no-light-split is a different cache key (renders again).
. test/cli/lib.sh
. test/cli/reference_lib.sh
ref_setup reference_split

"$PY" - "$D" <<'PYEOF'
import sys
d = sys.argv[1]
open(d + "/scene.json", "w").write('{"hair": {"procedural": {"style": "wavy", "strands": 200, '
    '"points": 8, "seed": 2}, "radius": 0.3}, "environment": {"file": "sky.hdr"}, '
    '"image": {"width": 32, "height": 24}, "quality": {"multiple_scattering": "off"}}\n')
PYEOF

ref() { "$SL" reference "$D/scene.json" --lights 16 --aa 4 --threads 2 "$@" 2>>"$D/stderr"; }
# field FILE.json EXPR: a value of the reference record, printed by python
field() { "$PY" -c 'import json,sys; r=json.load(open(sys.argv[1]))["reference"]; print(eval(sys.argv[2]))' "$1" "$2"; }

ok=1
ref -o "$D/full.exr" --no-light-split --no-convergence || ok=0
for s in 1 2 3 4 5 6 7 8; do ref -o "$D/split$s.exr" --seed "$s" --no-convergence || ok=0; done
if [ "$ok" != 1 ]; then
    fail reference_split_runs "$(tail -3 "$D/stderr")"
    exit 0
fi
# Unbiased: the mean G of the split images over 8 seeds against the every-light image (seed 1;
# its own ray sampling error is part of the comparison: same rays as the split's seed 1 only).
# Bound: 4 standard errors of the 8-seed mean (from the seeds' own scatter) plus 2 % for the
# every-light image's ray sampling; the test also requires that standard error to be below 8 %
# of the mean, so that it has the power to see a missing weight (x 16) or half of the lights
# lost (a subset of 1/16 of them is below its resolution).
full=$(field "$D/full.exr.json" 'r["mean_rgb"][1]')
means=$(for s in 1 2 3 4 5 6 7 8; do field "$D/split$s.exr.json" 'r["mean_rgb"][1]'; done | tr '\n' ' ')
if "$PY" - "$full" $means <<'PYEOF'
import sys, math
full = float(sys.argv[1]); m = [float(x) for x in sys.argv[2:]]
mu = sum(m) / len(m); sd = math.sqrt(sum((x - mu) ** 2 for x in m) / (len(m) - 1)); se = sd / math.sqrt(len(m))
print("every light %.5g, split mean %.5g, standard error %.3g (%.1f %%)" % (full, mu, se, 100 * se / mu), file=sys.stderr)
sys.exit(0 if full > 0 and se < 0.08 * mu and abs(mu - full) < 4 * se + 0.02 * full else 1)
PYEOF
then pass reference_split_unbiased; else fail reference_split_unbiased "every light $full, split: $means"; fi
# the split image is a different estimate (not the every-light image under another name)
if cmp -s "$D/full.exr" "$D/split1.exr"; then fail reference_split_differs "identical EXRs"; else pass reference_split_differs; fi
# coverage does not depend on which lights a ray shades (same rays: same seed)
cf=$(field "$D/full.exr.json" 'r["coverage"]')
cs=$(field "$D/split1.exr.json" 'r["coverage"]')
[ "$cf" = "$cs" ] && awk -v c="$cf" 'BEGIN { exit !(c > 0 && c < 1) }' && pass reference_split_same_coverage \
    || fail reference_split_same_coverage "coverage $cf vs $cs"
# deterministic whatever the thread count
"$SL" reference "$D/scene.json" --lights 16 --aa 4 --threads 1 --seed 1 --no-convergence -o "$D/t1.exr" 2>>"$D/stderr"
if cmp -s "$D/t1.exr" "$D/split1.exr"; then pass reference_split_threads_identical; else fail reference_split_threads_identical "threads 1 vs 2 differ"; fi
# the record
[ "$(field "$D/split1.exr.json" 'r["light_split"]')" = "True" ] && [ "$(field "$D/full.exr.json" 'r["light_split"]')" = "False" ] \
    && pass reference_split_json || fail reference_split_json "light_split not recorded"
# convergence: the 2N image uses seed + 1 (camera-ray sampling is part of the measured error)
if ref -o "$D/conv.exr" --seed 5; then
    s2=$(field "$D/conv.exr.json" 'r["convergence"]["seed_2n"]')
    b4=$(field "$D/conv.exr.json" 'r["convergence"]["rel_rmse_4x4"]')
    if [ "$s2" = "6" ] && awk -v b="$b4" 'BEGIN { exit !(b >= 0 && b < 10) }'; then pass reference_convergence_other_seed
    else fail reference_convergence_other_seed "seed_2n $s2, rel_rmse_4x4 $b4"; fi
else
    fail reference_convergence_other_seed "$(tail -2 "$D/stderr")"
fi
# --no-light-split is part of the cache key: the same path renders again, not "cached"
: >"$D/stderr"
ref -o "$D/split1.exr" --seed 1 --no-convergence --no-light-split
if grep -q "cached" "$D/stderr"; then fail reference_split_cache_key "reused the split image"; else pass reference_split_cache_key; fi
no_leftovers reference_split_no_temporaries "$D"
