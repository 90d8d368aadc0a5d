#!/bin/sh
# Quasi-static economy (issue 8, point 3; docs/economy.md, "Load rate"): the
# same case run at the paper's footing rate and at FACTOR times it, both
# with the case's ramp and local damping, cut at SETTLEMENT metres. Prints
# the footing load at every 0.025 m of settlement for both, the peak loads
# and their difference relative to the paper-rate peak, the largest
# kinetic/internal energy ratio of each, and the wall-time ratio.
# Usage: bench/economy_rate.sh [BUILD_DIR] [CASE] [FACTOR] [SETTLEMENT] [OUT]
#        (default build, geometries/slope_I_coarse.yaml, 5, 0.3,
#         /tmp/geoscni_economy_rate)
# The case's footing velocity is taken as the fast rate; the paper rate is
# it divided by FACTOR.
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-build}
case_file=${2:-$root/geometries/slope_I_coarse.yaml}
factor=${3:-5}
settlement=${4:-0.3}
out=${5:-/tmp/geoscni_economy_rate}
case_file=$(cd "$(dirname "$case_file")" && pwd)/$(basename "$case_file")
geoscni=$root/$build/bin/geoscni
[ -x "$geoscni" ] || { echo "no $geoscni: build first" >&2; exit 2; }
mkdir -p "$out"
speed=$(sed -n 's/.*footing: *{velocity: \[null, null, -\([0-9.e-]*\)\]}.*/\1/p' "$case_file")
ramp=$(sed -n 's/^ *ramp: *\([0-9.e-]*\).*/\1/p' "$case_file")
[ -n "$speed" ] || { echo "$case_file: no footing velocity [null, null, -V]" >&2; exit 2; }
ramp=${ramp:-0}
echo "$(basename "$case_file"): footing at $speed m/s against $speed/$factor m/s, to $settlement m ($(nproc) cores, load $(cut -d' ' -f1 /proc/loadavg))"
for run in fast paper; do
    v=$speed
    [ "$run" = paper ] && v=$(echo "$speed $factor" | awk '{print $1 / $2}')
    # The end time that gives the settlement after the ramp (half a ramp lost).
    end=$(echo "$settlement $v $ramp" | awk '{print $1 / $2 + $3 / 2}')
    every=$(echo "0.025 $v" | awk '{print $1 / $2}')
    mkdir -p "$out/$run"
    sed -e "s|^geometry: *|geometry: $(dirname "$case_file")/|" \
        -e "s|velocity: \[null, null, -$speed\]|velocity: [null, null, -$v]|" \
        -e "s|^\( *end:\).*|\1 $end|" -e "s|^\( *every:\).*|\1 $every|" \
        "$case_file" >"$out/$run/case.yaml"
    [ -f "$out/model.h5" ] || "$geoscni" pre "$out/$run/case.yaml" -o "$out" -q
    cp "$out/model.h5" "$out/$run/model.h5"
    start=$(date +%s.%N)
    "$geoscni" solve "$out/$run/case.yaml" -o "$out/$run" -q
    echo "$start $(date +%s.%N)" | awk '{printf "%.1f\n", $2 - $1}' >"$out/$run/wall"
done
. "$root/bench/economy_common.sh"
curve "$out/paper/history.csv" >"$out/paper.curve"
curve "$out/fast/history.csv" >"$out/fast.curve"
echo "settlement (m)   paper rate (MN)   fast (MN)   difference"
join "$out/paper.curve" "$out/fast.curve" |
    awk '{printf "  %.3f          %8.3f        %8.3f    %+.2f%%\n", $1, $2, $3, 100 * ($3 / $2 - 1)}'
peak_paper=$(awk 'BEGIN { m = 0 } $2 > m { m = $2 } END { print m }' "$out/paper.curve")
peak_fast=$(awk 'BEGIN { m = 0 } $2 > m { m = $2 } END { print m }' "$out/fast.curve")
ratio() { h5dump -a /kinetic_ratio_max "$1" 2>/dev/null | sed -n 's/.*(0): \(.*\)/\1/p' | head -1; }
echo "peak: paper rate $peak_paper MN, fast $peak_fast MN ($(echo "$peak_fast $peak_paper" | awk '{printf "%+.2f%%", 100 * ($1 / $2 - 1)}'))"
echo "largest kinetic/internal energy: paper rate $(ratio "$out/paper/results.h5"), fast $(ratio "$out/fast/results.h5")"
echo "wall time: paper rate $(cat "$out/paper/wall") s, fast $(cat "$out/fast/wall") s (ratio $(echo "$(cat "$out/paper/wall") $(cat "$out/fast/wall")" | awk '{printf "%.2f", $1 / $2}'))"
