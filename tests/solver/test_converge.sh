#!/bin/sh
# Issue 20, points 2 and 3: `geoscni converge` on the strip footing of
# test_bearing_capacity (geometries/strip_footing.yaml, smooth rigid footing,
# weightless paper soil, small strain, pushed at 0.1 m/s to 12.5% of B) at
# spacings 0.45, 0.3 and 0.2 m (4.4, 6.7 and 10 across B = 2 m), following
# the footing pressure (about 15 s):
# - the converged value lies within its own error estimate of Prandtl's
#   c N_c = 1.0568 MPa (REFERENCES.md), and the sequence is monotone with an
#   order in the asymptotic range (measured 2026-12-03: 0.89);
# - converge.csv has the three levels and the converged row, with the
#   printed value;
# - a second call finds every level done and gives the same line; a level
#   whose solve was stopped (SIGTERM: results.h5 not complete) is continued
#   from its checkpoint and gives the same value again;
# - the footing's force on this slab (two spacings thick) follows the
#   thickness: the default quantity turns into the pressure, a force asked
#   for is kept with a warning;
# - bad options end with exit 2 and the forms to use.
. ./cli_testing.sh
root=$(cd ../.. && pwd)
sed -e "s|^geometry: *|geometry: $root/geometries/|" \
    -e "s|velocity: \[null, null, -0.05\]|velocity: [null, null, -0.1]|" \
    -e "s|^\( *end:\).*|\1 2.75|" \
    "$root/geometries/strip_footing.yaml" >"$out/strip.yaml"
"$geoscni" converge "$out/strip.yaml" -o "$out/c" --quantity peak_pressure \
    --no-pictures >"$out/log" 2>&1 || fail "converge failed: $(tail -5 "$out/log")"
grep "^converge: observed order\|^converged value\|^converge: NOT" "$out/log"
line=$(grep "^converged value: " "$out/log")
value=$(echo "$line" | sed -n 's/^converged value: \([0-9.e+-]*\) Pa (estimated error \([0-9.e+-]*\) Pa.*/\1/p')
error=$(echo "$line" | sed -n 's/^converged value: \([0-9.e+-]*\) Pa (estimated error \([0-9.e+-]*\) Pa.*/\2/p')
awk -v v="${value:-0}" -v e="${error:-0}" 'BEGIN { d = v - 1.0568e6; if (d < 0) d = -d; exit !(v > 0 && e > 0 && d <= e) }' ||
    fail "c N_c = 1.0568e6 Pa is not within the estimate: '$line'"
grep -q "NOT IN THE ASYMPTOTIC RANGE" "$out/log" && fail "the strip footing's levels were not trusted"
[ "$(grep -c '^[123],' "$out/c/converge.csv")" -eq 3 ] || fail "converge.csv lacks a level: $(cat "$out/c/converge.csv")"
csv_value=$(sed -n 's/^converged,,,,\([^,]*\),.*/\1/p' "$out/c/converge.csv")
awk -v a="${csv_value:-0}" -v b="${value:-1}" 'BEGIN { exit !(a > 0 && (a - b) * (a - b) <= (1e-5 * b) ^ 2) }' ||
    fail "converge.csv's converged value $csv_value is not the printed $value"

# Again: every level found done, the same line.
"$geoscni" converge "$out/strip.yaml" -o "$out/c" --quantity peak_pressure \
    --no-pictures >"$out/log2" 2>&1 || fail "the second call failed: $(tail -3 "$out/log2")"
[ "$(grep -c 'solve skipped' "$out/log2")" -eq 3 ] || fail "the second call ran a level again"
[ "$(grep '^converged value: ' "$out/log2")" = "$line" ] || fail "the second call differs: $(grep '^converged value' "$out/log2")"

# The finest level stopped by SIGTERM once it runs, then the study again.
rm -rf "$out/c/level_3"
"$geoscni" converge "$out/strip.yaml" -o "$out/c" --quantity peak_pressure \
    --no-pictures >"$out/log3" 2>&1 &
study=$!
wait_for_file "$out/c/level_3/history.csv" 60
sleep 0.5
kill -TERM $study
wait $study
status=$?
[ $status -eq 130 ] || fail "the stopped study ended with $status, not 130: $(tail -3 "$out/log3")"
"$geoscni" converge "$out/strip.yaml" -o "$out/c" --quantity peak_pressure \
    --no-pictures >"$out/log4" 2>&1 || fail "the resumed study failed: $(tail -3 "$out/log4")"
grep -q "^restart: from the checkpoint at step" "$out/log4" || fail "the stopped level was not continued: $(grep -i 'level 3' -A3 "$out/log4")"
[ "$(grep '^converged value: ' "$out/log4")" = "$line" ] || fail "the resumed study differs: $(grep '^converged value' "$out/log4")"

# The force on this slab follows its thickness (two spacings): the default
# quantity turns into the pressure, a force asked for is kept with a warning.
"$geoscni" converge "$out/strip.yaml" -o "$out/c" --no-pictures >"$out/log5" 2>&1 ||
    fail "converge with the default quantity failed: $(tail -3 "$out/log5")"
grep -q "converge: the area of 'footing' changes with the spacing .*following the pressure on it instead" "$out/log5" ||
    fail "the default quantity did not turn into the pressure"
[ "$(grep '^converged value: ' "$out/log5")" = "$line" ] || fail "the default quantity's value differs from the pressure's"
"$geoscni" converge "$out/strip.yaml" -o "$out/c" --no-pictures --quantity peak_force >"$out/log6" 2>&1 ||
    fail "converge of the force failed: $(tail -3 "$out/log6")"
grep -q "warning: the area of 'footing' changes with the spacing .*--quantity peak_pressure" "$out/log6" ||
    fail "no warning that the footing's area follows the spacing"

# Other quantities on the same levels (each found done): the pressure at a
# settlement of 0.1 m lies below the peak, and the displacement under the
# footing's middle, 0.1 m down, between 0.1 m and the footing's 0.25 m.
"$geoscni" converge "$out/strip.yaml" -o "$out/c" --quantity pressure_at:0.1 \
    --no-pictures >"$out/log7" 2>&1 || fail "pressure_at failed: $(tail -3 "$out/log7")"
at=$(sed -n 's/^converge: level 3: pressure on .footing. at a settlement of 0.1 m = \([0-9.e+-]*\) Pa.*/\1/p' "$out/log7")
peak=$(sed -n 's/^converge: level 3: peak pressure on .footing. = \([0-9.e+-]*\) Pa.*/\1/p' "$out/log")
awk -v a="${at:-0}" -v p="${peak:-0}" 'BEGIN { exit !(a > 0.5 * p && a < p) }' ||
    fail "the pressure at 0.1 m ($at Pa) is not below the peak ($peak Pa)"
"$geoscni" converge "$out/strip.yaml" -o "$out/c" --quantity displacement_at:0.5,0.1,2.9 \
    --no-pictures >"$out/log8" 2>&1 || fail "displacement_at failed: $(tail -3 "$out/log8")"
u=$(sed -n 's/^converge: level 3: displacement at (0.5, 0.1, 2.9) m = \([0-9.e+-]*\) m.*/\1/p' "$out/log8")
awk -v u="${u:-0}" 'BEGIN { exit !(u > 0.1 && u < 0.25) }' ||
    fail "the displacement under the footing ($u m) is not between 0.1 and 0.25 m"
echo "level 3: pressure at 0.1 m $at Pa (peak $peak Pa), displacement under the footing $u m"

# The factor of safety as the quantity (issue 20, point 2): a fos study per
# level (Griffiths & Lane's slope at 2.25, 1.5 and 1 m: each level's factor
# between 1.3 and 1.5, bracketed to 0.0025); called again, every trial of
# every level is kept and the line is the same.
sed -e "s|^geometry: .*|geometry: $(pwd)/../../geometries/slope_gl.geo|" cases/gl_slope.yaml >"$out/gl.yaml"
"$geoscni" converge "$out/gl.yaml" -o "$out/f" --quantity factor_of_safety --finest 1.0 \
    --no-pictures >"$out/log9" 2>&1 || fail "converge of the factor of safety failed: $(tail -3 "$out/log9")"
grep "^converge: level [0-9]: factor of safety\|^converged value" "$out/log9"
levels=$(sed -n 's/^converge: level [0-9]: factor of safety = \([0-9.]*\) .*/\1/p' "$out/log9" | tr '\n' ' ')
for f in $levels; do
    awk -v f="$f" 'BEGIN { exit !(f > 1.3 && f < 1.5) }' || fail "a level's factor of safety $f is not between 1.3 and 1.5"
done
[ "$(echo $levels | wc -w)" -eq 3 ] || fail "not three levels' factors: $levels"
"$geoscni" converge "$out/gl.yaml" -o "$out/f" --quantity factor_of_safety --finest 1.0 \
    --no-pictures >"$out/log10" 2>&1 || fail "the second converge of the factor of safety failed"
[ "$(grep '^converged value' "$out/log9")" = "$(grep '^converged value' "$out/log10")" ] ||
    fail "the second study's line differs: $(grep '^converged value' "$out/log10")"
grep -q "from fos.csv" "$out/log10" && ! grep "^fos: factor" "$out/log10" | grep -vq "from fos.csv" ||
    fail "the second study ran trials again"

# Bad options.
for bad in "--levels 2" "--levels 3.5" "--ratio 1.05" "--tol 2" "--quantity peak" \
    "--quantity force_at:-1" "--quantity peak_force:nowhere" "--quantity displacement_at:1,2" \
    "--quantity factor_of_safety:footing"; do
    # shellcheck disable=SC2086
    "$geoscni" converge "$out/strip.yaml" -o "$out/bad" $bad >"$out/err" 2>&1
    status=$?
    [ $status -eq 2 ] || fail "converge $bad: exit $status, not 2"
    grep -q "levels\|ratio\|tol\|quantity\|boundary entry" "$out/err" || fail "converge $bad: message $(cat "$out/err")"
done
finish
