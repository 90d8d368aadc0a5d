#!/bin/sh
# Issue 19, point 5: solve states its memory need before it allocates and
# refuses a case that would not fit, with the numbers. The coarse Slope I
# (4,886 particles) for 20 steps, with the slope cases' NSNI and with MSCNI,
# and the thin slab of the deep-penetration footing (7,903 particles, two
# spacings thick, whose peak comes while its rows are built, since its
# plane-strain rollers are no longer constraints):
# - the stated need lies within 15% of the peak resident size measured by
#   /usr/bin/time (the estimate is a fit to 8 bodies, within 7% of them with
#   SCNI, docs/solver.md "Memory"; the rest is the allocator's and the
#   libraries' slack; before the boundary matrices were counted the slab's
#   need was stated 45% short);
# - under an address-space limit (ulimit -v) that leaves less room than the
#   need, solve ends with exit 2 before it allocates, naming the case, the
#   need and the limit, and writes no results.
. ./cli_testing.sh
root=$(cd ../.. && pwd)
make_case() { # NAME INTEGRATION
    sed -e "s|^geometry: *|geometry: $root/geometries/|" \
        -e "s|^integration:.*|integration: $2|" \
        -e "s|end: [0-9.]*|end: 0.02|" -e "s|ramp: [0-9.]*|ramp: 0.01|" \
        -e "s|^\(  step:\).*|\1 1.0e-3|" \
        "$root/geometries/slope_I_coarse.yaml" >"$out/$1.yaml"
}
make_case nsni "{method: scni, stabilization: nsni, coefficient: 0.1}"
make_case mscni "{method: scni, stabilization: mscni}"
sed -e "s|^geometry: *|geometry: $root/geometries/|" \
    -e "s|end: [0-9.]*|end: 0.03|" -e "s|ramp: [0-9.]*|ramp: 0.01|" \
    "$root/geometries/footing_penetration.yaml" >"$out/slab.yaml"
"$geoscni" pre "$out/nsni.yaml" -o "$out/m" -q || fail "pre failed"
"$geoscni" pre "$out/slab.yaml" -o "$out/s" -q || fail "pre of the slab failed"
for name in nsni mscni slab; do
    folder=$out/m
    [ $name = slab ] && folder=$out/s
    /usr/bin/time -f "peak %M KB" "$geoscni" solve "$out/$name.yaml" -o "$folder" \
        >"$out/$name.log" 2>&1 || fail "$name: solve failed: $(tail -3 "$out/$name.log")"
    need=$(sed -n 's/^solver: about \([0-9]*\) MB of memory needed.*/\1/p' "$out/$name.log")
    peak=$(sed -n 's/^peak \([0-9]*\) KB$/\1/p' "$out/$name.log")
    echo "$name: need stated $need MB, peak resident $(awk -v k="${peak:-0}" 'BEGIN { printf "%.0f", k * 1.024 / 1000 }') MB"
    awk -v n="${need:-0}" -v k="${peak:-0}" 'BEGIN { p = k * 1024 / 1e6; exit !(n > 0 && n <= 1.15 * p && n >= 0.85 * p) }' ||
        fail "$name: the stated need ($need MB) is not within 15% of the peak ($peak KB)"
done
rm -f "$out/m/results.h5" "$out/m/history.csv"
(ulimit -v 300000 && exec "$geoscni" solve "$out/mscni.yaml" -o "$out/m") >"$out/limited.log" 2>&1
status=$?
echo "under ulimit -v 300000: exit $status: $(grep error "$out/limited.log")"
[ $status -eq 2 ] || fail "a case over the address-space limit ended with $status, not 2"
grep -q "mscni.yaml: this case needs about [0-9]* MB of memory ([0-9]* particles, scni + mscni), but [0-9]* MB are available (the address-space limit (ulimit -v))" "$out/limited.log" ||
    fail "the refusal does not give the numbers: $(cat "$out/limited.log")"
[ -e "$out/m/results.h5" ] && fail "the refused solve wrote results.h5"
finish
