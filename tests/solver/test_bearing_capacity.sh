#!/bin/sh
# Bearing capacity of a smooth rigid strip footing (issue 7, point 2;
# docs/failure.md, section 5): geometries/strip_footing.yaml as it is
# (half the footing, B = 2 m = 10 spacings, SCNI, weightless soil with the
# paper's Drucker-Prager, associated flow, small-strain kinematics), pushed
# at 0.1 m/s to 12.5% of B. Prandtl-Reissner with the plane-strain match of
# the cone gives c N_c = 1.0568 MPa (REFERENCES.md).
# Checks, the issue's: the footing pressure (the force the footing applies,
# sum of its particles' multipliers, history.csv) at 10% and 12.5% of B
# within +0 to +10% of c N_c at 10 spacings (measured +4.2%; +1.3% with the
# force of before 2026-12-02 evening, which missed 2.7% of the work); the
# force does the footing's work, F = dW_ext/ds within 0.5% (0.13%);
# a plateau (the two within 1% of each other; large-deformation kinematics
# rise by 4% between them); kinetic energy below 1% of the internal energy
# (quasi-static).
# The mesh is gmsh's reproducible one (docs/pre.md): HXT's meshes differ
# from run to run and move the plateau by about 1%.
# usage: test_bearing_capacity.sh GEOSCNI   (run from tests/solver)
. ./cli_testing.sh
root=$(cd ../.. && pwd)
sed -e "s|^geometry: *|geometry: $root/geometries/|" \
    -e "s|velocity: \[null, null, -0.05\]|velocity: [null, null, -0.1]|" \
    -e "s|^\( *end:\).*|\1 2.75|" \
    "$root/geometries/strip_footing.yaml" >"$out/strip_footing.yaml"
grep -q "^kinematics: small" "$out/strip_footing.yaml" ||
    { echo "FAIL: strip_footing.yaml is not the small-strain case"; exit 1; }
"$geoscni" pre "$out/strip_footing.yaml" -o "$out" -q &&
    "$geoscni" solve "$out/strip_footing.yaml" -o "$out" -q ||
    { echo "FAIL: the run failed"; exit 1; }
ratio=$(h5dump -a /kinetic_ratio_max "$out/results.h5" |
    sed -n 's/.*(0): \(.*\)/\1/p' | head -1)
# q / (c N_c) at settlements of 10% and 12.5% of B, interpolated between
# rows; the footing area is b T = 1 m x 0.4 m (strip_footing.geo, T = 2h).
awk -F, -v ratio="$ratio" '
    NR == 1 { for (i = 1; i <= NF; ++i) { if ($i ~ /^footing_uz(_m)?$/) u = i; if ($i ~ /^footing_fz(_N)?$/) f = i
                                          if ($i == "external_work_J") w = i }; next }
    { s = -$u / 2.0; q = -$f / 0.4 / 1.0568e6
      # the force is the one whose work is the footing'"'"'s: F = dW_ext/ds
      # (central differences over the rows; the other supports are fixed)
      n++; S[n] = -$u; F[n] = -$f; W[n] = $w
      for (k = 1; k <= 2; ++k) { t = 0.075 + 0.025 * k
          if (!(k in at) && s >= t) at[k] = prev_q + (q - prev_q) * (t - prev_s) / (s - prev_s) }
      prev_s = s; prev_q = q }
    END {
        printf "q/(c Nc) at 10%% of B %.4f, at 12.5%% %.4f; kinetic/internal <= %s\n", at[1], at[2], ratio
        bad = 0
        if (!(2 in at)) { print "FAIL: the run did not reach 12.5% of B"; exit 1 }
        for (k = 1; k <= 2; ++k) if (!(at[k] >= 1.0 && at[k] <= 1.10)) { print "FAIL: not within +0 to +10% of c N_c"; bad = 1 }
        if (!(at[2] - at[1] < 0.01 && at[1] - at[2] < 0.01)) { print "FAIL: no plateau (changes by more than 1% from 10% to 12.5% of B)"; bad = 1 }
        if (!(ratio + 0 < 0.01)) { print "FAIL: not quasi-static"; bad = 1 }
        worst = 0
        for (k = 2; k < n; ++k) if (S[k] >= 0.05 && S[k + 1] > S[k - 1]) {
            d = (W[k + 1] - W[k - 1]) / (S[k + 1] - S[k - 1]) / F[k] - 1
            if (d < 0) d = -d
            if (d > worst) worst = d }
        printf "footing force against dW_ext/ds from 2.5%% of B on: worst %.2g\n", worst
        # 0.5%: central differences of the trapezoid work over rows 0.5% of
        # B apart give 0.13%; the force of before 2026-12-02 evening (traction
        # resultant plus reactions at the coefficients) was 2.7% under it
        if (!(worst <= 0.005)) { print "FAIL: the footing force does not do the footing'"'"'s work"; bad = 1 }
        exit bad }' "$out/history.csv"
