#!/bin/sh
# Issue 21, point 5: with time.ramp, gravity and tractions rise like the
# prescribed velocities, (1 - cos(pi t / T)) / 2, and the energy balance
# stays exact; without it, a warning with the ramp to set.
# - cases/load_ramp_box.yaml (elastic, undamped, gravity and a surcharge
#   ramped over 2.5 periods of the lowest mode): the top's force in
#   history.csv is the ramped surcharge times its 2 m^2 at every row (9
#   digits); the bottom carries the ramped weight and surcharge within 3%
#   from half the ramp on (the ringing measured: 1.0%); after the ramp the
#   kinetic energy stays below 1e-3 of the internal energy (measured 1.6e-4;
#   applied at once: 0.92); KE + W_int - W_ext stays below 1e-4 of W_ext
#   (measured 6e-6; the trapezoid's error is O(dt^2); applied at once the
#   jump at t = 0 costs 3%).
# - The same box without time.ramp warns that gravity and tractions are
#   applied at once, suggesting a ramp.
# - Reproducer gravity_damage (a stable berm slope under its own weight,
#   the paper's soil, damping 0.1): without a ramp it warns and self-weight
#   damages it (0.71 to 0.73 measured); with the ramp the warning suggests (1 s), no
#   damage at all.
. ./cli_testing.sh
"$geoscni" run cases/load_ramp_box.yaml -o "$out/box" --no-pictures -q 2>"$out/err" ||
    fail "the ramped box failed: $(cat "$out/err")"
grep -q "full value at t = 0" "$out/err" && fail "a ramped load was warned of: $(cat "$out/err")"
awk -F, -v ramp=0.2 'NR == 1 { for (i = 1; i <= NF; ++i) c[$i] = i; next }
    { t = $c["time_s"]; f = t < ramp ? 0.5 * (1 - cos(3.141592653589793 * t / ramp)) : 1
      top = $c["top_fz_N"]; bottom = $c["bottom_fz_N"]; load = f * (2000 * 2 * 9.81 + 2e4)
      ke = $c["kinetic_energy_J"]; wi = $c["internal_energy_J"]; we = $c["external_work_J"]
      d = top + f * 2e4; if (d < 0) d = -d; if (d > top_error) top_error = d
      if (t >= ramp / 2) { d = (bottom - load) / load; if (d < 0) d = -d; if (d > bottom_error) bottom_error = d }
      if (t >= ramp && wi > 0 && ke / wi > ratio) ratio = ke / wi
      d = ke + wi + $c["damping_work_J"] - we; if (d < 0) d = -d; if (d > balance) balance = d }
    END { printf "top force off by %.3g N, bottom by %.3g of the load, KE/W_int after the ramp %.3g, balance %.3g J of W_ext %.4g J\n",
              top_error, bottom_error, ratio, balance, we
          exit !(top_error <= 2e-3 && bottom_error <= 0.03 && ratio <= 1e-3 && balance <= 1e-4 * we) }' \
    "$out/box/history.csv" || fail "the ramped box is off (see above)"

sed -e 's/, ramp: 0.2}/}/' -e "s#^geometry: .*#geometry: $(cd ../.. && pwd)/geometries/box.geo#" \
    cases/load_ramp_box.yaml >"$out/sudden.yaml"
"$geoscni" pre "$out/sudden.yaml" -o "$out/sudden" -q && "$geoscni" solve "$out/sudden.yaml" -o "$out/sudden" -q 2>"$out/err" ||
    fail "the sudden box failed: $(cat "$out/err")"
grep -q "warning: $out/sudden.yaml: gravity and tractions are applied at full value at t = 0 (time.ramp is 0): .*'time: {ramp: 0.2}' raises the loads smoothly" "$out/err" ||
    fail "no warning of a sudden load: $(cat "$out/err")"

cp -r cases/repro "$out/repro"
damage() { awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) if ($i == "max_damage") c = i; next } { d = $c } END { print d }' "$1"; }
"$geoscni" run "$out/repro/gravity_damage.yaml" -o "$out/slope" --no-pictures -q 2>"$out/err" ||
    fail "gravity_damage failed: $(cat "$out/err")"
grep -q "gravity is applied at full value at t = 0 (time.ramp is 0): .*and damage, which counts every oscillation, grows; 'time: {ramp: 1}'" "$out/err" ||
    fail "gravity_damage: no warning: $(cat "$out/err")"
sudden=$(damage "$out/slope/history.csv")
sed -e 's/time: {end: 3.0, step: auto}/time: {end: 3.0, step: auto, ramp: 1}/' "$out/repro/gravity_damage.yaml" >"$out/repro/ramped.yaml"
"$geoscni" run "$out/repro/ramped.yaml" -o "$out/ramped" --no-pictures -q 2>"$out/err" ||
    fail "gravity_damage with a ramp failed: $(cat "$out/err")"
ramped=$(damage "$out/ramped/history.csv")
echo "gravity_damage: max damage $sudden applied at once, $ramped ramped over 1 s"
awk -v a="$sudden" -v b="$ramped" 'BEGIN { exit !(a > 0.3 && b == 0) }' ||
    fail "gravity_damage: damage $sudden at once and $ramped ramped"
finish
