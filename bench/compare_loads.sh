#!/bin/sh
# Two load-settlement curves from their history.csv files (for instance the
# uniform and the graded Slope I of bench/paper_slopes.sh): the footing load
# of each at every STEP m of settlement, their difference relative to the
# first, and the peaks (the largest |footing_fz| of the rows, and where).
# Usage: bench/compare_loads.sh HISTORY_A HISTORY_B [STEP]   (STEP 0.04 m)
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
[ $# -ge 2 ] || { sed -n 's/^# Usage: //p' "$0" >&2; exit 2; }
step=${3:-0.04}
. "$root/bench/economy_common.sh"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir "$work/a" "$work/b"
cp "$1" "$work/a/history.csv"
cp "$2" "$work/b/history.csv"
curve "$work/a/history.csv" "$step" >"$work/a.curve"
curve "$work/b/history.csv" "$step" >"$work/b.curve"
echo "settlement (m)   A (MN)   B (MN)   (B - A) / A"
join "$work/a.curve" "$work/b.curve" |
    awk '{printf "  %.3f        %7.3f  %7.3f   %+.1f%%\n", $1, $2, $3, 100 * ($3 / $2 - 1)}'
set -- $(peak a) $(peak b)
echo "$@" | awk '{printf "peak: A %.3f MN at %.3f m, B %.3f MN at %.3f m, (B - A) / A %+.2f%%\n", $1, $2, $3, $4, 100 * ($3 / $1 - 1)}'
