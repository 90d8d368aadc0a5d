#!/bin/sh
# Mass scaling through a run (time.mass_scaling, docs/solver.md "Mass
# scaling"): geometries/footing_penetration.yaml at B/5 (a smooth rigid
# strip footing pushed into weightless Tresca clay, plane strain, reference
# updates on by default) to half its width, with and without 1% of the
# body's mass added. Checks:
# - solve says where the mass went, and the step grows (measured 2026-12-07:
#   4.243 -> 4.903 ms at B/5; asked for 5%);
# - every reference update keeps the body's mass to 1e-12 and its momentum
#   as the unscaled run does (the interpolation's momentum is that of the
#   lumped masses, M = Lambda^T W 1, which the added mass would break:
#   4e-3 before that was fixed, 7e-7 to 5e-4 after, as without scaling);
# - the footing's pressure, averaged over 0.2-0.5 B, within 1% of the
#   unscaled run's (a quasi-static load: the masses do not enter the
#   equilibrium; measured 0.23%), and the energy balance within 1e-3 of
#   the work (measured 1.1e-6).
. ./cli_testing.sh
source_case=../../geometries/footing_penetration.yaml
geometry=$(cd ../../geometries && pwd)/footing_penetration.geo
sed -e "s|^geometry:.*|geometry: $geometry|" -e "s|^\( *spacing:\).*|\1 0.2|" \
    -e "s|^\( *end:\).*|\1 5.25|" "$source_case" >"$out/plain.yaml"
sed -e "s|^\( *\)step: auto.*|&\n\1mass_scaling: 0.01|" "$out/plain.yaml" >"$out/scaled.yaml"
grep -q "^  mass_scaling: 0.01" "$out/scaled.yaml" || fail "no mass_scaling in the case"
"$geoscni" pre "$out/plain.yaml" -o "$out/plain" -q || fail "pre failed"
mkdir -p "$out/scaled" && cp "$out/plain/model.h5" "$out/scaled/"
for name in plain scaled; do
    "$geoscni" solve "$out/$name.yaml" -o "$out/$name" >"$out/$name.log" 2>&1 ||
        fail "$name: solve ended with status $?: $(grep error "$out/$name.log")"
done
grep "^mass scaling: 1% of the body's mass added to" "$out/scaled.log" ||
    fail "solve does not say where the mass went"
grep -q "^mass scaling" "$out/plain.log" && fail "mass scaling without the key"
step_of() { sed -n 's/^time step: \([0-9.e-]*\) s.*/\1/p' "$1"; }
plain_step=$(step_of "$out/plain.log") scaled_step=$(step_of "$out/scaled.log")
echo "time step: $plain_step s without, $scaled_step s with"
awk -v a="$plain_step" -v b="$scaled_step" 'BEGIN { exit !(b > 1.05 * a) }' ||
    fail "the step did not grow"
# mass and momentum kept by every update, the momentum as well as without
# the added mass (at B/5 both runs' updates reach 1.9e-3)
momentum() {
    sed -n 's/.*, mass \([0-9.e+-]*\), momentum \([0-9.e+-]*\),.*/\1 \2/p' "$out/$1.log" |
        awk -v name="$1" '{ n++; if ($1 > m) m = $1; if ($2 > p) p = $2 }
            END { printf "%s: %d updates, mass error <= %.2g, momentum <= %.2g\n", name, n, m, p > "/dev/stderr"
                  if (n > 0 && m <= 1e-12) print p; else print -1 }'
}
plain_momentum=$(momentum plain) scaled_momentum=$(momentum scaled)
awk -v a="$plain_momentum" -v b="$scaled_momentum" \
    'BEGIN { exit !(a >= 0 && b >= 0 && b <= 1.5 * a + 1e-9) }' ||
    fail "an update lost mass or momentum, or none ran"
# the pressure over 0.2-0.5 B, and the energy balance
mean_force() {
    awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) col[$i] = i; next }
        { s = -$col["footing_uz_m"]; x = $col["external_work_J"]
          b = $col["energy_balance_J"]; if (b < 0) b = -b
          if (x > w) w = x; if (b > e) e = b
          if (s >= 0.2 && s <= 0.5) { f += -$col["footing_fz_N"]; n++ } }
        END { printf "%.6g %.3g\n", f / n, e / w }' "$1/history.csv"
}
set -- $(mean_force "$out/plain") $(mean_force "$out/scaled")
echo "footing force over 0.2-0.5 B: $1 N without, $3 N with; energy balance $2 and $4 of the work"
awk -v a="$1" -v b="$3" -v e="$4" 'BEGIN { d = (b - a) / a; if (d < 0) d = -d
    printf "difference %.2g\n", d; exit !(d <= 0.01 && e <= 1e-3) }' ||
    fail "the scaled run's pressure or energy balance is off"
finish
