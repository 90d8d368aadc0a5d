#!/bin/sh
# The speed-and-accuracy chart (issue 7, point 1): one elastic problem with a
# closed-form answer solved at several particle spacings with SCNI, SCNI +
# MSCNI, SCNI + NSNI, DNI, Gauss 2x2x2 and Gauss 3x3x3 (METHODS="..." runs
# some of them); the error and the times (wall clock and CPU) of every run
# go to a CSV, and error against time (log-log,
# with each method's convergence rate against spacing in the legend) to a
# PNG. The chart's time is the CPU time of a 1-thread run (build + steps):
# on a shared machine, what the run would take on an idle core.
#
# Usage: bench/accuracy_chart.sh [BUILD_DIR] [OUT_DIR] [PROBLEMS...]
#        (default build, docs/img, the problems `column` and
#        `column_jittered`)
# Writes OUT_DIR/accuracy.csv (all problems) and OUT_DIR/accuracy_PROBLEM.png.
# Runs one at a time on THREADS threads (default 1).
#
# Another problem: add it to the `problems` table of bench/accuracy_run.c
# (its particle box, initial state, samples and error), give it a case file
# bench/accuracy/NAME.yaml (or an entry below) and its spacings below.
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-build}
out=${2:-$root/docs/img}
[ $# -gt 2 ] && shift 2 || set --
problems=${*:-column column_jittered}
threads=${THREADS:-1}
methods=${METHODS:-scni mscni nsni dni gauss2 gauss3}
run=$root/$build/bin/accuracy_run
plot=$root/$build/bin/accuracy_plot
[ -x "$run" ] && [ -x "$plot" ] || { echo "no $run or $plot: build first" >&2; exit 2; }
mkdir -p "$out"

# The case file and the spacings (m) of each problem.
case_of() {
    case $1 in
    column | column_jittered) echo "$root/bench/accuracy/column.yaml" ;;
    *) echo "$root/bench/accuracy/$1.yaml" ;;
    esac
}
spacings_of() {
    case $1 in
    column | column_jittered) echo "0.5 0.25 0.125 0.0625" ;;
    *) echo "unknown problem $1: give it spacings in $0" >&2; exit 2 ;;
    esac
}
title_of() {
    case $1 in
    column) echo "Standing-wave column, f1 = c_p/(4H), regular lattice" ;;
    column_jittered) echo "Standing-wave column, layers jittered by +-0.2h" ;;
    *) echo "$1" ;;
    esac
}

label_of() {
    case $1 in
    column | column_jittered) echo "relative L2 error of u over 2 periods" ;;
    *) echo "error" ;;
    esac
}

csv=$out/accuracy.csv
tmp=$csv.part
"$run" --header >"$tmp"
started=$(date +%s)
echo "accuracy chart: $problems; $(nproc) cores, load $(cut -d' ' -f1 /proc/loadavg), $threads thread(s) a run"
for problem in $problems; do
    for h in $(spacings_of "$problem"); do
        for method in $methods; do
            row=$("$run" "$problem" "$(case_of "$problem")" "$method" "$h" "$threads")
            echo "$row" >>"$tmp"
            echo "  $row"
        done
    done
done
mv "$tmp" "$csv"
for problem in $problems; do
    echo "$problem: $out/accuracy_$problem.png"
    "$plot" "$csv" "$problem" "$out/accuracy_$problem.png" \
        "$(title_of "$problem")" "$(label_of "$problem")"
done
echo "took $(($(date +%s) - started)) s; load $(cut -d' ' -f1 /proc/loadavg)"
