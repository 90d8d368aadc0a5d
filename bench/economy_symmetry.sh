#!/bin/sh
# Symmetry economy (issue 8, point 1): the whole Slope II against its half
# cut at the mid-plane y = 6 with a symmetry plane. Runs pre and solve of
# both cases with time.end cut to END seconds (default 2.5 s: 0.2 m of footing
# settlement at the coarse cases' 0.1 m/s after their 1 s ramp), then prints the particle counts, the wall times of
# pre + solve, the peak footing loads (the half's doubled: its history holds
# the force on half the footing), the difference of the peaks relative to the
# whole slope's, and the wall-time ratio half / whole.
# Usage: bench/economy_symmetry.sh [BUILD_DIR] [END] [WHOLE_CASE] [HALF_CASE]
#        (default build, 2.5, geometries/slope_II_coarse.yaml,
#        geometries/slope_II_half_coarse.yaml; the paper-resolution run:
#        bench/economy_symmetry.sh build 100.5 geometries/slope_II.yaml
#        geometries/slope_II_half.yaml)
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-build}
end=${2:-2.5}
whole=${3:-$root/geometries/slope_II_coarse.yaml}
half=${4:-$root/geometries/slope_II_half_coarse.yaml}
. "$root/bench/economy_common.sh"
economy_setup symmetry
t_whole=$(run whole "$whole")
t_half=$(run half "$half")
n_whole=$(particles whole)
n_half=$(particles half)
set -- $(peak whole 1)
p_whole=$1 u_whole=$2
set -- $(peak half 2)
p_half=$1 u_half=$2
echo "whole $(basename "$whole"): $n_whole particles, pre + solve $t_whole s, peak footing load $p_whole MN at $u_whole m"
echo "half  $(basename "$half"): $n_half particles, pre + solve $t_half s, peak footing load (doubled) $p_half MN at $u_half m"
echo "$p_whole $p_half $t_whole $t_half" |
    awk '{printf "peak difference (half doubled - whole) / whole: %+.2f %%\nwall-time ratio half / whole: %.3f\n", 100 * ($2 - $1) / $1, $4 / $3}'
