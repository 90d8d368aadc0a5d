#!/bin/sh
# geoscni run skips a stage whose output was made from the same parameters
# and from inputs of the same contents (hashes stored in the outputs, not
# modification times): a second run skips all three; a changed material
# reruns solve and post but not pre; a touched geometry (same contents)
# skips all three; a changed geometry with an old modification time reruns
# everything, and so does --rerun.
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
[ "$(skipped)" -eq 3 ] || fail "a touched geometry (same contents) skipped $(skipped) stages, expected 3"
echo "// edited" >>"$work/box.geo"
touch -d "2000-01-01" "$work/box.geo"
run "$work/case.yaml"
[ "$(skipped)" -eq 0 ] || fail "a changed geometry older than the outputs skipped $(skipped) stages"
# results.h5 of other contents (one value of its last frame changed, with
# an old modification time) reruns post but not solve, whose inputs are
# the same
/usr/bin/python3 -c '
import sys, zlib, h5py, numpy as np
with h5py.File(sys.argv[1], "r+") as f:
    last = sorted(f["frames"])[-1]
    damage = f["frames"][last]["damage"]
    damage[0] += 0.5
    # as a writer would: with the checksum of the new data (h5io.c)
    damage.attrs["crc32"] = np.uint32(zlib.crc32(damage[()].tobytes()))
' "$work/out/results.h5" || fail "cannot change results.h5 (h5py)"
touch -d "2000-01-01" "$work/out/results.h5"
run "$work/case.yaml"
grep -q "solve skipped" "$work/log" || fail "changed results reran solve"
grep -q "post skipped" "$work/log" && fail "other results.h5 contents did not rerun post"
run "$work/case.yaml" --rerun
[ "$(skipped)" -eq 0 ] || fail "--rerun skipped a stage"
finish
