#!/bin/sh
# geoscni run skips a stage whose output is newer than its inputs and was
# made from the same parameters: a second run skips all three; a changed
# material reruns solve and post but not pre; a touched geometry reruns
# everything; --rerun reruns everything.
. ./cli_testing.sh
work=$out
cp ../../geometries/box.geo "$work/box.geo"
sed 's|^geometry: .*|geometry: box.geo|' cases/cli_box.yaml >"$work/case.yaml"
sed 's|^material: {density: 2000|material: {density: 2100|' "$work/case.yaml" >"$work/heavier.yaml"

run() { "$geoscni" run "$@" --no-pictures -o "$work/out" >"$work/log" 2>&1 || fail "run $* failed: $(cat "$work/log")"; }
skipped() { grep -c "skipped" "$work/log"; }

run "$work/case.yaml"
[ "$(skipped)" -eq 0 ] || fail "first run skipped a stage"
run "$work/case.yaml"
[ "$(skipped)" -eq 3 ] || fail "second run skipped $(skipped) stages, expected 3"
cp "$work/heavier.yaml" "$work/case.yaml"
run "$work/case.yaml"
grep -q "pre skipped" "$work/log" || fail "a changed material reran pre"
grep -q "solve skipped" "$work/log" && fail "a changed material did not rerun solve"
sleep 1
touch "$work/box.geo"
run "$work/case.yaml"
[ "$(skipped)" -eq 0 ] || fail "a touched geometry skipped $(skipped) stages"
run "$work/case.yaml" --rerun
[ "$(skipped)" -eq 0 ] || fail "--rerun skipped a stage"
finish
