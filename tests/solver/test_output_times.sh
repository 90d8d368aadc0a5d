#!/bin/sh
# Frames at listed times through the CLI (issue 8, point 4; docs/economy.md,
# "Outputs"): cases/times_box.yaml with output.times alone, then with
# output.every added; check_output_times.py finds each frame at the step
# nearest its time in results.h5, the .pvd and history.csv.
# usage: test_output_times.sh GEOSCNI   (run from tests/solver)
. ./cli_testing.sh
times="0.013 0.049 0.05 0.0801"

"$geoscni" run cases/times_box.yaml -o "$out/times" --no-pictures -q ||
    fail "run times_box"
/usr/bin/python3 check_output_times.py "$out/times" times_box 0.1 0 $times ||
    fail "output.times alone"

# with output.every: the union, 0.04 s from both lists once
sed -e 's|^output: {times: \[0.013, |output: {every: 0.04, times: [0.013, 0.04, |' \
    -e 's|^geometry: \.\./\.\./\.\./|geometry: '"$PWD"'/../../|' cases/times_box.yaml \
    >"$out/times_every.yaml"
grep -q "every: 0.04, times: \[0.013, 0.04, 0.049" "$out/times_every.yaml" ||
    fail "the case with output.every was not made"
"$geoscni" run "$out/times_every.yaml" -o "$out/both" --no-pictures -q ||
    fail "run times_every"
/usr/bin/python3 check_output_times.py "$out/both" times_every 0.1 0.04 \
    $times 0.04 || fail "output.times with output.every"
finish
