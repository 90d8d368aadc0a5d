#!/bin/sh
# plane_strain: y holds u_y at zero in every coefficient
# (cases/plane_strain_elastic.yaml):
# - u_y is exactly 0 at every particle in every frame, and the velocity too;
# - sigma_yy = nu (sigma_xx + sigma_zz) at every particle to 1e-9 of the
#   largest stress (round-off of the smoothed gradients and the stress sums);
# - small kinematics and large, plain SCNI and MSCNI, with reference
#   updates (the velocity interpolated at an update keeps u_y = 0);
# - negative control: without plane_strain the block bulges in y (|u_y|
#   above 1e-4 m) and the relation fails by more than 1e-2.
# - the case file refuses an unknown axis, naming the line.
. ./cli_testing.sh
check() { # FOLDER EXPECT: held (u_y, v_y and the stress relation), u_y (u_y alone) or free
    /usr/bin/python3 - "$1/results.h5" "$2" <<'PY'
import sys, h5py, numpy as np
K, G = 27.4e6, 9.15e6
nu = (3 * K - 2 * G) / (2 * (3 * K + G))
frames = h5py.File(sys.argv[1], "r")["frames"]
uy = max(np.abs(frames[f]["displacement"][:, 1]).max() for f in frames)
vy = max(np.abs(frames[f]["velocity"][:, 1]).max() for f in frames)
worst = 0.0
for f in frames:
    s = frames[f]["stress"][:]
    scale = max(np.abs(s).max(), 1.0)
    worst = max(worst, np.abs(s[:, 1] - nu * (s[:, 0] + s[:, 2])).max() / scale)
print(f"max |u_y| {uy:.3g} m, max |v_y| {vy:.3g} m/s, sigma_yy - nu (sigma_xx + sigma_zz): {worst:.3g} of the largest stress")
expect = sys.argv[2]
ok = {"held": uy == 0.0 and vy == 0.0 and worst < 1e-9, "u_y": uy == 0.0,
      "free": uy > 1e-4 and worst > 1e-2}[expect]
sys.exit(0 if ok else 1)
PY
}
sed -e "s#^geometry: .*#geometry: $(pwd)/cases/plane_strain_box.geo#" \
    cases/plane_strain_elastic.yaml >"$out/small.yaml"
"$geoscni" run "$out/small.yaml" -o "$out/small" -q --no-pictures || fail "small: run failed"
check "$out/small" held || fail "small kinematics: u_y not held or the stress relation off"
sed -e 's/^kinematics: small/kinematics: large/' "$out/small.yaml" >"$out/large.yaml"
"$geoscni" run "$out/large.yaml" -o "$out/large" -q --no-pictures || fail "large: run failed"
check "$out/large" u_y || fail "large kinematics: u_y not held"
{ sed -e 's/^integration:.*/integration: scni/' "$out/large.yaml"
  echo "reference_update: {every: 0.05, min_steps: 1}"; } >"$out/updates.yaml"
"$geoscni" run "$out/updates.yaml" -o "$out/updates" -q --no-pictures || fail "updates: run failed"
check "$out/updates" u_y || fail "with reference updates: u_y not held"
updates=$(awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == "reference_updates") c = i; next }
                   { v = $c } END { print v }' "$out/updates/history.csv")
[ "${updates:-0}" -ge 3 ] || fail "expected reference updates in the run, got ${updates:-none}"
grep -v '^plane_strain' "$out/small.yaml" >"$out/free.yaml"
"$geoscni" run "$out/free.yaml" -o "$out/free" -q --no-pictures || fail "free: run failed"
check "$out/free" free || fail "negative control: without plane_strain u_y should not be 0"
sed -e 's/^plane_strain: y/plane_strain: w/' "$out/small.yaml" >"$out/bad.yaml"
"$geoscni" check "$out/bad.yaml" >"$out/bad.log" 2>&1
[ $? -eq 2 ] && grep -q "bad.yaml:[0-9]*: 'plane_strain' must be one of" "$out/bad.log" ||
    fail "a bad axis: $(cat "$out/bad.log")"
finish
