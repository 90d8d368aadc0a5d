#!/bin/sh
# Issue 22, point 3: geoscni ground turns a grid of elevations and layer
# thicknesses (or grids of layer bottoms) into a gmsh geometry whose named
# surfaces and volumes a case file uses: geometries/site_survey.xyz with
# fill 2 m, clay 6 m and rock to a base at 5 m meshes into three volumes
# whose particles lie between the layers' elevations; a layer given by the
# grid of its bottom; bad grids and layers are refused with the file, the
# line or the place, and what to change.
. ./cli_testing.sh
survey=$(pwd)/../../geometries/site_survey.xyz
"$geoscni" ground "$survey" --layers fill:2,clay:6,rock --base 5 -o "$out/site.geo" >"$out/log" 2>&1 ||
    fail "ground failed: $(cat "$out/log")"
grep -q "^ground: -> .*site.geo: surfaces ground, base, xmin, xmax, ymin, ymax; volumes fill clay rock" "$out/log" ||
    fail "no summary line: $(cat "$out/log")"
cat >"$out/site.yaml" <<CASE
geometry: site.geo
particles: {spacing: 3.0}
materials:
  fill: {density: 1800, bulk_modulus: 20e6, shear_modulus: 8e6}
  clay: {density: 1900, bulk_modulus: 30e6, shear_modulus: 10e6}
  rock: {density: 2400, bulk_modulus: 2e9, shear_modulus: 1e9}
gravity: [0, 0, -9.81]
boundary:
  base: {fix: [x, y, z]}
  xmin: {fix: [x]}
  xmax: {fix: [x]}
  ymin: {fix: [y]}
  ymax: {fix: [y]}
time: {end: 0.01, step: auto}
CASE
"$geoscni" pre "$out/site.yaml" -o "$out/site" >"$out/pre.log" 2>&1 || fail "pre of the site failed: $(tail -3 "$out/pre.log")"
grep -q "^pre: volumes fill [0-9]* particles, clay [0-9]* particles, rock [0-9]* particles" "$out/pre.log" ||
    fail "pre does not see the three layers: $(grep '^pre' "$out/pre.log")"
"$geoscni" check "$out/site.yaml" >"$out/check.log" 2>&1 || fail "check of the site failed: $(tail -3 "$out/check.log")"
grep -q "free" "$out/check.log" && grep "free" "$out/check.log"
# every particle between its layer's top and bottom (the ground, less the
# thicknesses, bilinear on the grid), within the spacing
/usr/bin/python3 - "$survey" "$out/site/model.h5" <<'PY' || fail "particles outside their layers"
import sys
import h5py
import numpy as np
grid = np.loadtxt(sys.argv[1])
xs, ys = np.unique(grid[:, 0]), np.unique(grid[:, 1])
z = np.zeros((len(ys), len(xs)))
for x, y, e in grid:
    z[np.searchsorted(ys, y), np.searchsorted(xs, x)] = e
def ground(x, y):
    i = min(np.searchsorted(xs, x, side="right") - 1, len(xs) - 2)
    j = min(np.searchsorted(ys, y, side="right") - 1, len(ys) - 2)
    s, t = (x - xs[i]) / (xs[i + 1] - xs[i]), (y - ys[j]) / (ys[j + 1] - ys[j])
    # the two triangles of the cell, split along its (i, j)-(i+1, j+1) diagonal
    if s >= t:
        return z[j, i] + s * (z[j, i + 1] - z[j, i]) + t * (z[j + 1, i + 1] - z[j, i + 1])
    return z[j, i] + t * (z[j + 1, i] - z[j, i]) + s * (z[j + 1, i + 1] - z[j + 1, i])
with h5py.File(sys.argv[2], "r") as m:
    x = m["particles/position"][:]
    names = [n.decode() if isinstance(n, bytes) else n for n in m["volumes/name"][:]]
    owner = m["particles/physical_volume"][:]
bounds = {"fill": (2.0, 0.0), "clay": (8.0, 2.0), "rock": (None, 8.0)}
worst = 0.0
for p, o in zip(x, owner):
    g = ground(p[0], p[1])
    low, high = bounds[names[o]]
    bottom = 5.0 if low is None else g - low
    top = g - high
    worst = max(worst, bottom - p[2], p[2] - top)
print(f"particles outside their layer by {worst:.2e} m at most (1e-6)")
sys.exit(0 if worst <= 1e-6 else 1)
PY
# a layer down to the grid of its own bottom: the clay's bottom 8 m under
# the ground, as a file, gives the same geometry
awk '/^#/ { next } NF == 3 { print $1, $2, $3 - 8 }' "$survey" >"$out/clay_bottom.xyz"
"$geoscni" ground "$survey" --layers "fill:2,clay:$out/clay_bottom.xyz,rock" --base 5 -o "$out/site2.geo" -q ||
    fail "ground with a bottom grid failed"
# the same entities; the points' elevations to round-off (z - 8 as text)
/usr/bin/python3 - "$out/site.geo" "$out/site2.geo" <<'PY' ||
import re, sys
a, b = (open(f).read().splitlines()[1:] for f in sys.argv[1:])
number = re.compile(r"-?[0-9]+(?:\.[0-9]*)?(?:e[-+]?[0-9]+)?")
same = len(a) == len(b) and all(
    number.sub("#", p) == number.sub("#", q) and
    all(abs(float(x) - float(y)) <= 1e-9 for x, y in zip(number.findall(p), number.findall(q)))
    for p, q in zip(a, b))
sys.exit(0 if same else 1)
PY
    fail "a bottom grid 8 m down differs from a thickness of 6 m under 2 m"

# errors
expect() { # STATUS PATTERN WHAT, then the command
    status=$1 pattern=$2 what=$3
    shift 3
    "$@" >/dev/null 2>"$out/err"
    got=$?
    [ $got -eq "$status" ] && grep -q "$pattern" "$out/err" || fail "$what: exit $got: $(cat "$out/err")"
}
head -20 "$survey" >"$out/short.xyz"
expect 2 "short.xyz: 17 points on 17 x values and 1 y values\|short.xyz: the points lie on one line" "a grid of one row" \
    "$geoscni" ground "$out/short.xyz" --layers fill:2,rock --base 5 -o "$out/x.geo"
sed '5d' "$survey" >"$out/hole.xyz"
expect 2 "hole.xyz: 230 points on 21 x values and 11 y values: not a full grid" "a grid with a hole" \
    "$geoscni" ground "$out/hole.xyz" --layers fill:2,rock --base 5 -o "$out/x.geo"
sed '7s/.*/3.0 0.0 abc/' "$survey" >"$out/text.xyz"
expect 2 "text.xyz:7: expected three numbers 'x y z' (m)" "a line of text" \
    "$geoscni" ground "$out/text.xyz" --layers fill:2,rock --base 5 -o "$out/x.geo"
expect 2 "site_survey.xyz: at (0, 0) the layer 'fill' would run from 20.001 m down to 18.001 m: below --base; give a lower base or thinner layers" "a base above the layers" \
    "$geoscni" ground "$survey" --layers fill:2,clay:6,rock --base 25 -o "$out/x.geo"
expect 2 "give the last layer without a thickness" "no last layer" \
    "$geoscni" ground "$survey" --layers fill:2,clay:6 --base 5 -o "$out/x.geo"
expect 2 "ground needs --layers" "no layers" "$geoscni" ground "$survey" --base 5
[ -e "$out/x.geo" ] && fail "a refused ground left $out/x.geo"
finish
