#!/bin/sh
# Large-deformation perfect plasticity, homogeneous (docs/failure.md,
# section 5): cases/plane_strain_compression.yaml in both kinematics. Once
# the block flows, sigma_zz = -sqrt(2) R (von Mises in plane strain), so the
# top force at a compression eps is sqrt(2) R A0 / (1 - eps) with large
# kinematics (the isochoric flow widens the block) and sqrt(2) R A0 with
# small. Checked at eps = 10% and 25% within 1.5%: the elastic volume
# change (|p| / K, about 0.5%) and the damped ripple of the explicit run are
# below it; forgetting the area change (or adding it to small strain) would
# miss by 11% and 33%.
# usage: test_plastic_compression.sh GEOSCNI   (run from tests/solver)
. ./cli_testing.sh
for kinematics in large small; do
    mkdir -p "$out/$kinematics"
    sed -e "s|^geometry: *|geometry: $(pwd)/cases/|" \
        -e "s|^kinematics:.*|kinematics: $kinematics|" \
        cases/plane_strain_compression.yaml >"$out/$kinematics/case.yaml"
    "$geoscni" pre "$out/$kinematics/case.yaml" -o "$out/$kinematics" -q &&
        "$geoscni" solve "$out/$kinematics/case.yaml" -o "$out/$kinematics" -q ||
        { fail "the $kinematics run failed"; continue; }
    awk -F, -v kinematics="$kinematics" '
        NR == 1 { for (i = 1; i <= NF; ++i) { if ($i == "zmax_uz_m") u = i; if ($i == "zmax_fz_N") f = i }; next }
        { e = -$u; F = -$f
          for (k = 1; k <= 2; ++k) { t = k == 1 ? 0.10 : 0.25
              if (!(k in at) && e >= t - 1e-9) at[k] = prev_F + (F - prev_F) * (t - prev_e) / (e - prev_e) }
          prev_e = e; prev_F = F }
        END {
            bad = 0
            for (k = 1; k <= 2; ++k) {
                t = k == 1 ? 0.10 : 0.25
                expected = sqrt(2) * 0.19e6 / (kinematics == "large" ? 1 - t : 1)
                if (!(k in at)) { print "FAIL: " kinematics " did not reach " t; bad = 1; continue }
                d = at[k] / expected - 1
                printf "%s kinematics, eps %.2f: top force %.5g N, expected %.5g N (%+.2f%%)\n", kinematics, t, at[k], expected, 100 * d
                if (!(d < 0.015 && d > -0.015)) { print "FAIL: off by more than 1.5%"; bad = 1 }
            }
            exit bad }' "$out/$kinematics/history.csv" || fail "$kinematics: the top force is off its closed form"
done
finish
