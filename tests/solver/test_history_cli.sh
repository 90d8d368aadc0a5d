#!/bin/sh
# Issue 21, point 8.
# - history.csv carries its units in its column names and stays a plain
#   CSV: the exact header of cases/cli_box.yaml, and every row read as
#   numbers by Python's csv module and by numpy.genfromtxt(names=True).
# - A traction entry reports the force it applies: a box with a traction of
#   5 kPa along x on its 1 m^2 face xmax reports xmax_fx_N = 5000 N at every
#   row, t = 0 included (applied at once); its other components 0.
# - Progress into a file comes at least every GEOSCNI_PROGRESS_SECONDS
#   (here 0.01 s), with an ETA, not only at every tenth of the run (which
#   gives at most 11 lines).
# - Errors say what is wrong without geoscni's internal chain ("raised in
#   ... from ..."), for every command; --verbose (-v) adds it.
. ./cli_testing.sh
root=$(cd ../.. && pwd)
"$geoscni" run cases/cli_box.yaml -o "$out/box" --no-pictures -q 2>/dev/null || fail "run cli_box failed"
expected="time_s,step,bottom_ux_m,bottom_uy_m,bottom_uz_m,bottom_fx_N,bottom_fy_N,bottom_fz_N,top_ux_m,top_uy_m,top_uz_m,top_fx_N,top_fy_N,top_fz_N,kinetic_energy_J,internal_energy_J,external_work_J,max_damage,damping_work_J,reference_updates,update_energy_J,failed_particles,energy_balance_J"
[ "$(head -1 "$out/box/history.csv")" = "$expected" ] || fail "header: $(head -1 "$out/box/history.csv")"
/usr/bin/python3 - "$out/box/history.csv" <<'PY' || fail "history.csv is not a plain numeric CSV for csv and numpy"
import csv, sys
import numpy
rows = list(csv.DictReader(open(sys.argv[1])))
values = [float(v) for r in rows for v in r.values()]
table = numpy.genfromtxt(sys.argv[1], delimiter=",", names=True)
assert len(rows) == 6 and table.shape == (6,), (len(rows), table.shape)
assert numpy.all(numpy.isfinite(table.view((float, len(table.dtype.names)))))
assert table["top_fz_N"][-1] == float(rows[-1]["top_fz_N"]) < 0
print("history.csv: %d rows of %d columns read by csv and numpy" % (len(rows), len(table.dtype.names)))
PY

printf 'geometry: %s\nparticles: {spacing: 0.25}\nmaterial: {density: 2000, bulk_modulus: 1.0e7, shear_modulus: 5.0e6}\nboundary:\n  bottom: {fix: [x, y, z]}\n  xmax: {traction: [5.0e3, 0, 0]}\ntime: {end: 0.05, step: auto}\noutput: {every: 0.01}\n' \
    "$root/geometries/box.geo" >"$out/pulled.yaml"
"$geoscni" run "$out/pulled.yaml" -o "$out/pulled" --no-pictures -q 2>/dev/null || fail "run of the pulled box failed"
awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) c[$i] = i; next }
    { rows++; d = $c["xmax_fx_N"] - 5000; if (d < 0) d = -d; if (d > worst) worst = d
      if ($c["xmax_fy_N"] != 0 || $c["xmax_fz_N"] != 0) other = 1 }
    END { printf "traction entry xmax: %d rows, fx off 5000 N by at most %.3g N\n", rows, worst
          exit !(rows >= 6 && worst <= 1e-6 && !other) }' "$out/pulled/history.csv" ||
    fail "the traction entry's force is not the 5000 N it applies"

sed -e "s#^geometry: .*#geometry: $root/geometries/box.geo#" -e 's/end: 1000/end: 40/' \
    cases/cli_box_long.yaml >"$out/long.yaml"
"$geoscni" pre "$out/long.yaml" -o "$out/long" -q || fail "pre failed"
GEOSCNI_PROGRESS_SECONDS=0.01 "$geoscni" solve "$out/long.yaml" -o "$out/long" >/dev/null 2>"$out/progress" ||
    fail "the long solve failed"
lines=$(grep -c "^step [0-9]*/[0-9]*  t = .* s .*%  \(ETA\|took\) " "$out/progress")
echo "progress: $lines lines"
[ "$lines" -gt 15 ] || fail "only $lines progress lines: $(cat "$out/progress")"

for command in "check ../foundation/cases/bad/zero_density.yaml" \
    "pre ../foundation/cases/bad/zero_density.yaml -o $out/e" \
    "solve cases/cli_box.yaml -o $out/no_model" "post $out/no_results" \
    "run ../foundation/cases/bad/zero_density.yaml -o $out/e"; do
    # shellcheck disable=SC2086
    "$geoscni" $command >/dev/null 2>"$out/err"
    [ $? -eq 2 ] || fail "$command: exit status, expected 2"
    grep -q "error: " "$out/err" || fail "$command: no message: $(cat "$out/err")"
    grep -q "raised in\|^  from " "$out/err" && fail "$command: the internal chain is shown: $(cat "$out/err")"
    # shellcheck disable=SC2086
    "$geoscni" $command --verbose >/dev/null 2>"$out/err"
    grep -q "raised in" "$out/err" || fail "$command --verbose: no chain: $(cat "$out/err")"
done
finish
