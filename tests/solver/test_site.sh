#!/bin/sh
# Issue 22: layers (a material per gmsh physical volume) and a static water
# table, on cases/layered_column.yaml (three soils, 1 x 1 x 6 m):
# - pre names the volumes and counts their particles; a particle off an
#   interface carries its layer (check_site.py);
# - one-dimensional compression: the top settles q sum(h_i / M_i); the
#   error is first order in the spacing (the kernels are smooth across an
#   interface): within 3% at 0.25 m and smaller at 0.125 m;
# - the geostatic stage of the column under its weight with the water
#   table at 4.5 m: effective sigma'_v = -sum(rho g h) + u layer by layer
#   and each layer's elastic K0; with geostatic.k0 the stresses of the
#   layered, wet column set first (the columns' weight, gsn_overburden);
# - post writes the volume and the pore pressure into the .vtu;
# - the errors of materials: and water: name the file, line and fix.
. ./cli_testing.sh
sed "s|^geometry: .*|geometry: $(pwd)/cases/layered_column.geo|" cases/layered_column.yaml >"$out/column.yaml"
"$geoscni" run "$out/column.yaml" -o "$out/c" --no-pictures >"$out/log" 2>&1 ||
    fail "the compression run failed: $(tail -3 "$out/log")"
grep -q "^pre: volumes sand [0-9]* particles, clay [0-9]* particles, fill [0-9]* particles" "$out/log" ||
    fail "pre does not name the volumes: $(grep '^pre' "$out/log")"
/usr/bin/python3 check_site.py compression "$out/c" 0.03 >"$out/c.txt" || fail "the compression at 0.25 m: $(cat "$out/c.txt")"
cat "$out/c.txt"
sed "s|spacing: 0.25|spacing: 0.125|" "$out/column.yaml" >"$out/fine.yaml"
"$geoscni" run "$out/fine.yaml" -o "$out/f" --no-pictures -q >"$out/f.log" 2>&1 ||
    fail "the compression at 0.125 m failed: $(tail -3 "$out/f.log")"
/usr/bin/python3 check_site.py compression "$out/f" 0.03 >"$out/f.txt" || fail "the compression at 0.125 m: $(cat "$out/f.txt")"
cat "$out/f.txt"
coarse=$(sed -n 's/.*error \([-+0-9.e]*\)$/\1/p' "$out/c.txt")
fine=$(sed -n 's/.*error \([-+0-9.e]*\)$/\1/p' "$out/f.txt")
# first order: the error at half the spacing at most 0.7 of the coarse one
awk -v c="$coarse" -v f="$fine" 'BEGIN { if (c < 0) c = -c; if (f < 0) f = -f
    printf "error %.4f at 0.25 m, %.4f at 0.125 m (ratio %.2f)\n", c, f, c / f
    exit !(f <= 0.7 * c) }' || fail "the settlement's error does not fall with the spacing"

# The column under its weight, the water table at 4.5 m.
sed -e "s|^  top: .*|  top: {}|" -e "/^damping/d" \
    -e "s|^time: .*|time: {end: 0.01, step: auto}\ngravity: [0, 0, -9.81]\nwater: {level: 4.5}\ngeostatic: on|" \
    -e "s|^output: .*|output: {every: 0.01}|" "$out/column.yaml" >"$out/wet.yaml"
"$geoscni" run "$out/wet.yaml" -o "$out/w" >"$out/w.log" 2>&1 || fail "the wet column failed: $(tail -3 "$out/w.log")"
/usr/bin/python3 check_site.py geostatic "$out/w" 4.5 || fail "check_site.py geostatic"
grep -q "^soils: sand [0-9]* particles, clay [0-9]* particles, fill [0-9]* particles$" "$out/w.log" &&
    grep -q "^water: a level table, gamma_w 9.81 kN/m^3: pore pressure up to 44.15 kPa" "$out/w.log" ||
    fail "solve does not say its soils and water: $(grep '^soils\|^water' "$out/w.log")"
for field in volume pore_pressure; do
    grep -aq "Name=\"$field\"" "$out/w/vtu/frame_0000.vtu" || fail "the .vtu has no $field"
done
# every soil as heavy as water, under 2 m of it: the pore force and the
# water on the faces carry the weight, sigma' should vanish; it does to the
# integration's accuracy for a hydrostatic u (measured 1.8% of u at the
# base, 0.25 m spacing; 2.5%)
sed -e "s/saturated_density: [0-9]*/saturated_density: 1000/g" -e "s|^water: .*|water: {level: 8}|" \
    "$out/wet.yaml" >"$out/afloat.yaml"
"$geoscni" run "$out/afloat.yaml" -o "$out/a" --no-pictures >"$out/a.log" 2>&1 || fail "the afloat column failed: $(tail -3 "$out/a.log")"
/usr/bin/python3 - "$out/a/results.h5" <<'PY' || fail "sigma' of a column as heavy as water does not vanish"
import sys
import h5py
import numpy as np
with h5py.File(sys.argv[1], "r") as r:
    stress = r["frames"][sorted(r["frames"].keys())[0]]["stress"][:]
largest, u = np.abs(stress).max(), 9810.0 * 8.0
print(f"afloat: |sigma'| at most {largest:.0f} Pa, {largest / u:.4f} of u at the base (0.025)")
sys.exit(0 if largest <= 0.025 * u else 1)
PY
# a table spread over the site: the plane 4.4 + 0.1 x + 0.2 y through the
# column's corners (linear on their triangles: the plane itself)
sed -e "s|^water: .*|water: {table: [[0, 0, 4.4], [1, 0, 4.5], [0, 1, 4.6], [1, 1, 4.7]]}|" \
    "$out/wet.yaml" >"$out/tilted.yaml"
"$geoscni" run "$out/tilted.yaml" -o "$out/t" --no-pictures >"$out/t.log" 2>&1 || fail "the tilted table failed: $(tail -3 "$out/t.log")"
/usr/bin/python3 check_site.py geostatic "$out/t" 4.4,0.1,0.2 || fail "check_site.py geostatic with a tilted table"
sed -e "s|^geostatic: on|geostatic: {k0: 0.5}|" "$out/wet.yaml" >"$out/k0.yaml"
"$geoscni" run "$out/k0.yaml" -o "$out/k" --no-pictures >"$out/k.log" 2>&1 || fail "the K0 run failed: $(tail -3 "$out/k.log")"
grep -q "^geostatic: at rest after [0-9]* steps of [0-9.e-]* s (the stresses of level ground set first, K0 = 0.5)" "$out/k.log" ||
    fail "no K0 line: $(grep geostatic "$out/k.log")"
/usr/bin/python3 check_site.py geostatic "$out/k" 4.5 0.5 || fail "check_site.py geostatic with K0 0.5"

# Errors: each names the file (and line) and what to change.
expect_error() { # CASE PATTERN WHAT
    "$geoscni" check "$1" >/dev/null 2>"$out/err"
    status=$?
    [ $status -eq 2 ] && grep -q "$2" "$out/err" || fail "$3: exit $status: $(cat "$out/err")"
}
sed "s|^  clay: |  clays: |" "$out/column.yaml" >"$out/bad1.yaml"
expect_error "$out/bad1.yaml" "bad1.yaml:9: 'materials.clays' names no physical volume of .*layered_column.geo; did you mean 'clay'? (it has: sand, clay, fill)" \
    "a material naming no volume"
sed "/^  fill: /d" "$out/column.yaml" >"$out/bad2.yaml"
expect_error "$out/bad2.yaml" "physical volume 'fill' has no soil in .*bad2.yaml: add 'fill: {density" \
    "a volume without a material"
sed "s|^materials:|material: {density: 1800, bulk_modulus: 1e7, shear_modulus: 5e6}\nmaterials:|" "$out/column.yaml" >"$out/bad3.yaml"
expect_error "$out/bad3.yaml" "bad3.yaml:[0-9]*: give either 'material' (one soil for the whole body) or 'materials'" \
    "both material and materials"
sed "s|^time: |water: {level: 3}\ntime: |" "$out/column.yaml" >"$out/bad4.yaml"
expect_error "$out/bad4.yaml" "bad4.yaml:[0-9]*: 'water' gives a water table, whose pore pressure is the water's weight: give gravity too" \
    "water without gravity"
sed "s|^time: |gravity: [0, 0, -9.81]\nwater: {table: [[0, 0, 4], [2, 0, 5], [1, 0, 5]]}\ntime: |" "$out/column.yaml" >"$out/bad5.yaml"
expect_error "$out/bad5.yaml" "bad5.yaml:[0-9]*: 'water.table\[2\]' does not go on from the point before it" \
    "a water table going back"
# one material for several volumes: a warning, and the run goes on
sed -e "/^  [a-z]*: {density/d" -e "s|^materials:|material: {density: 1800, bulk_modulus: 2e7, shear_modulus: 8e6}|" \
    "$out/column.yaml" >"$out/one.yaml"
"$geoscni" pre "$out/one.yaml" -o "$out/one" -q 2>"$out/err" || fail "pre of one soil failed: $(cat "$out/err")"
grep -q "warning: .*one.yaml: .*layered_column.geo has 3 physical volumes, and 'material' gives them all one soil" "$out/err" ||
    fail "no warning for one soil in three volumes: $(cat "$out/err")"
finish
