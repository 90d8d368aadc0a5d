#!/bin/sh
# Issue 18, point 2: the geostatic stage. cases/geostatic_column.yaml (a
# 1 x 1 x 4 m elastic column, rollers on its sides, 456 particles):
# - a surface with a prescribed velocity is free during the stage: the
#   loading starts with no force on it and the weight on the bottom;
# - solve says the body came to rest (steps, the unbalanced force against
#   its limit) and results.h5 keeps the stage's steps, residual and time;
# - check_geostatic.py: the frame at t = 0 holds sigma_v = rho g z and
#   sigma_h = K0 sigma_v (layer means; the integral to 1e-3) with zero
#   displacements, and the loading stage that follows stays at rest;
# - with geostatic.k0 = 0.4 the layers keep that K0 (the stresses of level
#   ground set first, then relaxed);
# - stopped in the loading stage and continued with --restart, the run
#   ends with the same bits as one never stopped (the stage is not run
#   again: its state is in the checkpoint);
# - a budget too small for the stage ends with exit 3 and the numbers, and
#   keeps the state it reached as the one frame of results.h5; a
#   stage with nothing to bring to rest, or beside a rigid body, exit 2.
. ./cli_testing.sh
sed "s|^geometry: .*|geometry: $(pwd)/cases/column.geo|" cases/geostatic_column.yaml >"$out/column.yaml"
"$geoscni" run "$out/column.yaml" -o "$out/a" --no-pictures >"$out/log" 2>&1 ||
    fail "the run failed: $(tail -3 "$out/log")"
grep "^geostatic:" "$out/log"
grep -q "^geostatic: at rest after [0-9]* steps of [0-9.e-]* s (the dead loads raised over [0-9]*): unbalanced force [0-9.e-]* of the load (limit 0.0001)" "$out/log" ||
    fail "no geostatic line: $(head -5 "$out/log")"
/usr/bin/python3 check_geostatic.py "$out/a" || fail "check_geostatic.py"

# The K0 procedure: the stresses of level ground set first (K0 = 0.4, not
# the elastic 0.538), which the relaxation keeps.
sed -e "s|^geostatic: on|geostatic: {k0: 0.4}|" "$out/column.yaml" >"$out/k0.yaml"
"$geoscni" run "$out/k0.yaml" -o "$out/k0" --no-pictures >"$out/k0.log" 2>&1 ||
    fail "the K0 run failed: $(tail -3 "$out/k0.log")"
grep -q "^geostatic: at rest after [0-9]* steps of [0-9.e-]* s (the stresses of level ground set first, K0 = 0.4)" "$out/k0.log" ||
    fail "no K0 line: $(grep geostatic "$out/k0.log")"
/usr/bin/python3 check_geostatic.py "$out/k0" 0.4 || fail "check_geostatic.py with K0 0.4"

# Longer, stopped once the loading stage runs, then continued.
sed -e "s|^time: .*|time: {end: 10.0, step: auto}|" -e "s|^output: .*|output: {every: 1.0}|" \
    "$out/column.yaml" >"$out/long.yaml"
"$geoscni" run "$out/long.yaml" -o "$out/straight" --no-pictures -q || fail "the long run failed"
"$geoscni" pre "$out/long.yaml" -o "$out/stopped" -q || fail "pre failed"
"$geoscni" solve "$out/long.yaml" -o "$out/stopped" -q 2>"$out/err" &
stop_at_rows $! "$out/stopped/history.csv" 3
status=$stopped_status
[ $status -eq 130 ] || echo "note: the solve ended before the signal ($status)"
"$geoscni" solve "$out/long.yaml" -o "$out/stopped" --restart >"$out/restart.log" 2>&1 ||
    [ $status -eq 0 ] || fail "the restart failed: $(tail -3 "$out/restart.log")"
grep -q "^geostatic:" "$out/restart.log" && fail "the restart ran the geostatic stage again"
cmp -s "$out/straight/history.csv" "$out/stopped/history.csv" ||
    fail "the continued run's history.csv differs from the straight run's"

# A surface that will move is free while the body settles: pushed from the
# top, the column starts with no force on the top and its whole weight on
# the bottom (1880 * 9.81 * 4 m^3).
sed -e "s|^  ymax: {fix: \[y\]}|  ymax: {fix: [y]}\n  top: {velocity: [null, null, -0.01]}|" \
    -e "s|^time: .*|time: {end: 0.2, step: auto, ramp: 0.1}|" \
    "$out/column.yaml" >"$out/pushed.yaml"
"$geoscni" run "$out/pushed.yaml" -o "$out/pushed" --no-pictures -q || fail "the pushed column failed"
awk -F, 'NR == 1 { for (k = 1; k <= NF; ++k) column[$k] = k }
         NR == 2 { top = $column["top_fz_N"]; bottom = $column["bottom_fz_N"] }
         END { w = 1880 * 9.81 * 4; printf "t = 0: top %g N, bottom %g N (weight %g N)\n", top, bottom, w
               d = bottom - w; if (d < 0) d = -d
               exit !(top == 0 && d <= 1e-3 * w) }' "$out/pushed/history.csv" ||
    fail "the pushed column does not start free at its top with its weight on its bottom"

# Errors.
sed -e "s|^geostatic: on|geostatic: {max_steps: 40}|" "$out/column.yaml" >"$out/short.yaml"
"$geoscni" run "$out/short.yaml" -o "$out/short" --no-pictures >"$out/short.log" 2>&1
status=$?
[ $status -eq 3 ] || fail "a stage over its budget ended with $status, not 3"
grep -q "short.yaml: the body found no rest under its dead loads within 40 steps (geostatic.max_steps): the unbalanced force is still [0-9.e+-]* of the load.*; the state it reached is the one frame of .*short/results.h5" "$out/short.log" ||
    fail "budget message: $(grep error "$out/short.log")"
[ -s "$out/short/results.h5" ] && [ -s "$out/short/short.pvd" ] ||
    fail "the failed stage did not keep its state (results.h5, and run's post of it)"
sed -e "s|^gravity: .*|gravity: [0, 0, 0]|" "$out/column.yaml" >"$out/weightless.yaml"
"$geoscni" check "$out/weightless.yaml" >/dev/null 2>"$out/err"
[ $? -eq 2 ] && grep -q "'geostatic' brings the dead loads to equilibrium, but there are none" "$out/err" ||
    fail "a weightless geostatic case: $(cat "$out/err")"
finish
