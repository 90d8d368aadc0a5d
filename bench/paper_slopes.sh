#!/bin/sh
# The paper's slopes at its resolution, end to end (issue 6, point 6):
# geometries/slope_I.yaml and slope_II.yaml with the footing at FACTOR times
# the paper's rate after the case's 1 s ramp (bench/economy_rate.sh shows
# what the rate changes), the stable step chosen by the solver, cut at
# SETTLEMENT metres. Times each stage and prints particles, steps, the
# footing's peak load and where it occurs.
# RIGID=1 makes the footing a rigid body the soil cannot enter (rigid: true,
# docs/solver.md "Rigid bodies"). INTEGRATION replaces the case's
# integration (e.g. "{method: scni, stabilization: mscni}"); UPDATE sets
# reference_update (e.g. "off" or "{strain: 0.2, min_steps: 20}");
# WINDOW_CUT sets kernel.window_cut (docs/kernels.md, "Window cut");
# MASS_SCALING sets time.mass_scaling (docs/solver.md, "Mass scaling").
# Usage: [RIGID=1] [INTEGRATION=...] [UPDATE=...] [WINDOW_CUT=...] [MASS_SCALING=...]
#        bench/paper_slopes.sh [BUILD_DIR] [OUT]
#        [FACTOR] [SETTLEMENT] [CASES]
#        (default build, out/paper, 5, 1.0, "slope_I slope_II")
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-build}
out=${2:-$root/out/paper}
factor=${3:-5}
settlement=${4:-1.0}
cases=${5:-slope_I slope_II}
rigid=${RIGID:+, rigid: true}
integration=${INTEGRATION:-}
update=${UPDATE:-}
geoscni=$root/$build/bin/geoscni
[ -x "$geoscni" ] || { echo "no $geoscni: build first" >&2; exit 2; }
mkdir -p "$out"
seconds() { date +%s.%N; }
elapsed() { echo "$1 $(seconds)" | awk '{printf "%.0f", $2 - $1}'; }
for name in $cases; do
    source_case=$root/geometries/$name.yaml
    speed=$(sed -n 's/.*footing: *{velocity: \[null, null, -\([0-9.e-]*\)\]}.*/\1/p' "$source_case")
    v=$(echo "$speed $factor" | awk '{print $1 * $2}')
    end=$(echo "$settlement $v" | awk '{print $1 / $2 + 0.5}')
    every=$(echo "$settlement $v" | awk '{print $1 / $2 / 40}')
    mkdir -p "$out/$name"
    case_file=$out/$name/$name.yaml
    { [ -z "$update" ] || echo "reference_update: $update"
    sed -e "s|^geometry: *|geometry: $root/geometries/|" \
        -e "s|velocity: \[null, null, -$speed\]|velocity: [null, null, -$v]$rigid|" \
        -e "s|^\( *end:\).*|\1 $end|" -e "s|^\( *step:\).*|\1 auto|" \
        -e "${MASS_SCALING:+s|^\( *\)step:.*|&\n\1mass_scaling: $MASS_SCALING|}" \
        -e "s|^\( *every:\).*|\1 $every|" \
        -e "${integration:+s|^integration:.*|integration: $integration|}" \
        "$source_case"; } >"$case_file"
    [ -z "${WINDOW_CUT:-}" ] ||
        sed -i -e "s|^\( *\)support:\(.*\)|\1support:\2\n\1window_cut: $WINDOW_CUT|" "$case_file"
    echo "$name: footing at $v m/s to $settlement m ($(nproc) cores, load $(cut -d' ' -f1 /proc/loadavg))"
    t=$(seconds)
    "$geoscni" pre "$case_file" -o "$out/$name" -q
    pre=$(elapsed "$t")
    t=$(seconds)
    "$geoscni" solve "$case_file" -o "$out/$name" >"$out/$name/solve.log" 2>&1 || {
        echo "solve failed: $out/$name/solve.log" >&2; tail -5 "$out/$name/solve.log" >&2; }
    solve=$(elapsed "$t")
    t=$(seconds)
    "$geoscni" post "$out/$name" -q
    post=$(elapsed "$t")
    particles=$(h5ls "$out/$name/model.h5/particles/position" | sed -n 's/.*{\([0-9]*\),.*/\1/p')
    steps=$(tail -1 "$out/$name/history.csv" | cut -d, -f2)
    peak=$(awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) { if ($i ~ /^footing_uz(_m)?$/) u = i; if ($i ~ /^footing_fz(_N)?$/) f = i }; next }
        -$f > m { m = -$f; s = -$u } END { printf "%.2f MN at %.3f m", m / 1e6, s }' "$out/$name/history.csv")
    echo "  $particles particles, $steps steps; pre $pre s, solve $solve s, post $post s; peak footing load $peak"
    grep -E "quasi-static|warning|^reference updates|^failed particles" "$out/$name/solve.log" | sed "s/^/  /" || true
    # where it ended: failed particles, the energy balance over the work,
    # and the particles thrown up (u_z > 0.5 m at the last frame: the lip
    # of docs/paper_slopes.md)
    /usr/bin/python3 - "$out/$name" <<'PY' || true
import csv, sys, h5py
out = sys.argv[1]
rows = list(csv.DictReader(open(f"{out}/history.csv")))
col = lambda k: [float(r[k]) for r in rows]
balance = col("energy_balance_J")  # the energy check's (docs/solver.md, "Time step")
frames = h5py.File(f"{out}/results.h5", "r")["frames"]
uz = frames[sorted(frames.keys())[-1]]["displacement"][:, 2]
print(f"  at the end (t = {rows[-1]['time_s']} s): {rows[-1]['failed_particles']} failed particles; "
      f"|energy balance| <= {max(map(abs, balance)) / max(col('external_work_J')):.1e} of the work; "
      f"{int((uz > 0.5).sum())} particles up more than 0.5 m (highest {uz.max():.2f} m)")
PY
done
