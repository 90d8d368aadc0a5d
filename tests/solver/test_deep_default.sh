#!/bin/sh
# Issue 15, point 7: a case that ended with exit 3 now passes as it is.
# geometries/footing_penetration.yaml (a smooth rigid strip footing pushed
# one width into weightless Tresca clay) at B/5, nothing added: the default
# reference updates take it to 1 B with exit 0 (updates counted in
# history.csv, solve saying so); negative control, 'reference_update: off':
# the first reference cannot follow the soil around the footing's corner
# and the run ends with exit 3 (measured at 0.61 B).
. ./cli_testing.sh
source_case=../../geometries/footing_penetration.yaml
geometry=$(cd ../../geometries && pwd)/footing_penetration.geo
sed -e "s|^geometry:.*|geometry: $geometry|" -e "s|^\( *spacing:\).*|\1 0.2|" \
    "$source_case" >"$out/default.yaml"
{ echo "reference_update: off"; cat "$out/default.yaml"; } >"$out/off.yaml"
for name in default off; do
    status=0
    "$geoscni" run "$out/$name.yaml" -o "$out/$name" --no-pictures \
        >"$out/$name.log" 2>&1 || status=$?
    eval "status_$name=$status"
    # the footing's settlement over B and the updates at the last row
    eval "$(awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) col[$i] = i; next }
        { w = -$col["footing_uz_m"]; u = $col["reference_updates"] }
        END { printf "reach=%.4f updates=%d\n", w, u }' "$out/$name/history.csv")"
    eval "reach_$name=$reach updates_$name=$updates"
    echo "$name: exit $status at $reach B, $updates updates"
done
grep -q "^reference updates: on, the default" "$out/default.log" ||
    fail "solve does not say the updates are on by default"
[ "$status_default" -eq 0 ] || fail "default: exit $status_default"
awk -v w="$reach_default" 'BEGIN { exit !(w > 0.99) }' ||
    fail "default: reached $reach_default B, not 1 B"
[ "$updates_default" -gt 0 ] || fail "default: no update"
[ "$status_off" -eq 3 ] || fail "off: exit $status_off, expected 3"
awk -v w="$reach_off" 'BEGIN { exit !(w < 0.9) }' ||
    fail "off: reached $reach_off B, expected to stop short of 0.9 B"
[ "$updates_off" -eq 0 ] || fail "off: $updates_off updates"
finish
