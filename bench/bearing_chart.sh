#!/bin/sh
# The bearing-capacity chart (issue 7, point 1, the second chart): the
# strip footing of bench/bearing_capacity.sh in small-strain kinematics at
# several spacings with each integration, the error of the limit load
# (|q at 12.5% of B / (c N_c) - 1|) against the CPU time of the solve on
# log-log axes, the legend giving each method's rate against spacing
# (drawn by bench/accuracy_plot, like the elastic chart). Runs that stop
# before 12.5% of B are left off the chart and kept in the runs' CSV.
# Usage: bench/bearing_chart.sh [BUILD_DIR] [OUT_DIR] [SPACINGS] [METHODS]
#        (default build, docs/img, "0.4 0.286 0.2 0.133 0.1",
#        "scni mscni nsni nsni0.1 dni gauss2 gauss3": nsni0.1 is NSNI with
#        coefficient 0.1; Gauss at GAUSS_SPACINGS, default
#        "0.4 0.286 0.2"); runs in $RUNS (default
#        /tmp/geoscni_bearing_chart), one at a time on $THREADS threads
#        (default 1).
# Writes OUT_DIR/bearing_capacity.csv and OUT_DIR/bearing_capacity.png.
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-build}
out=${2:-$root/docs/img}
spacings=${3:-0.4 0.286 0.2 0.133 0.1}
methods=${4:-scni mscni nsni nsni0.1 dni gauss2 gauss3}
runs=${RUNS:-/tmp/geoscni_bearing_chart}
plot=$root/$build/bin/accuracy_plot
[ -x "$plot" ] || { echo "no $plot: build first" >&2; exit 2; }
mkdir -p "$out"
# Gauss points cost 8 (2x2x2) or 27 (3x3x3) stress updates a tetrahedron:
# those methods run the coarser spacings only (GAUSS_SPACINGS).
gauss_spacings=${GAUSS_SPACINGS:-0.4 0.286 0.2}
for method in $methods; do
    case $method in
    gauss*) method_spacings=$gauss_spacings ;;
    *) method_spacings=$spacings ;;
    esac
    OMP_NUM_THREADS=${THREADS:-1} sh "$root/bench/bearing_capacity.sh" \
        "$build" "$runs/$method" "$method_spacings" "$method" small
done
# The runs that reached 12.5% of B, one header.
for method in $methods; do cat "$runs/$method/bearing_capacity.csv"; done |
    awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) if ($i == "status") c = i; print; next }
             $1 != "spacing" && $c == "ok"' >"$out/bearing_capacity.csv"
"$plot" "$out/bearing_capacity.csv" strip_footing_small \
    "$out/bearing_capacity.png" \
    "Strip footing, small strain: limit load against CPU time" \
    "|q / (c N_c) - 1| at 12.5% of B"
