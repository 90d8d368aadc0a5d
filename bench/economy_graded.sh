#!/bin/sh
# Graded-spacing economy (issue 8, point 2): Slope I with uniform particles
# against the graded case (fine under the footing and along the slope face,
# coarse far away). Runs pre and solve of both with time.end cut to END
# seconds (default 3.5 s: 0.15 m of footing settlement at the coarse cases'
# 0.05 m/s after their 1 s ramp, past the peak at about 0.1 m), then prints the particle counts, the
# time steps, the wall times of pre + solve, the peak footing loads, their
# difference relative to the uniform case's, and the wall-time ratio
# graded / uniform.
# Usage: bench/economy_graded.sh [BUILD_DIR] [END] [UNIFORM_CASE] [GRADED_CASE]
#        (default build, 3.5, geometries/slope_I_coarse.yaml,
#        geometries/slope_I_graded_coarse.yaml; the paper-resolution run:
#        bench/economy_graded.sh build 100.5 geometries/slope_I.yaml
#        geometries/slope_I_graded.yaml)
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-build}
end=${2:-3.5}
uniform=${3:-$root/geometries/slope_I_coarse.yaml}
graded=${4:-$root/geometries/slope_I_graded_coarse.yaml}
. "$root/bench/economy_common.sh"
economy_setup graded
t_uniform=$(run uniform "$uniform")
t_graded=$(run graded "$graded")
set -- $(peak uniform)
p_uniform=$1 u_uniform=$2
set -- $(peak graded)
p_graded=$1 u_graded=$2
echo "uniform $(basename "$uniform"): $(particles uniform) particles, step $(step uniform) s, pre + solve $t_uniform s, peak footing load $p_uniform MN at $u_uniform m"
echo "graded  $(basename "$graded"): $(particles graded) particles, step $(step graded) s, pre + solve $t_graded s, peak footing load $p_graded MN at $u_graded m"
grep '^pre: \(refine\|outside\)' "$work/graded.pre.log" | sed 's/^/  /'
echo "$p_uniform $p_graded $t_uniform $t_graded" |
    awk '{printf "peak difference (graded - uniform) / uniform: %+.2f %%\nwall-time ratio graded / uniform: %.3f\n", 100 * ($2 - $1) / $1, $4 / $3}'
