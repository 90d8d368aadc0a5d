#!/bin/sh
# Cost against the number of particles (issue 17): Slope I (the case's
# integration, damage and Drucker-Prager) at spacings that give about
# 1e4 to 1e6 particles; per size the wall time of pre, the solver's set-up,
# the step rate over STEPS steps and the peak resident memory of pre and of
# the solve, per particle (pre's time with its meshing by gmsh apart).
# Linear cost shows as flat columns per particle.
# Each size runs once (pre and set-up take minutes at 1e6): a trend, not a
# median; the step rate column is the one to repeat with solver_bench.sh.
# Usage: bench/scaling.sh [BUILD_DIR] [STEPS] [CASE]
#        (default build, 20, geometries/slope_I.yaml); COUNTS="1e4 3e4
#        1e5 3e5 1e6" and THREADS=2 (default) in the environment
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-build}
steps=${2:-20}
case_file=${3:-$root/geometries/slope_I.yaml}
counts=${COUNTS:-1e4 3e4 1e5 3e5 1e6}
threads=${THREADS:-2}
geoscni=$root/$build/bin/geoscni
[ -x "$geoscni" ] || { echo "no $geoscni: build first" >&2; exit 2; }
[ -x /usr/bin/time ] || { echo "needs GNU time: apt-get install time" >&2; exit 2; }
work=$(mktemp -d /tmp/geoscni_scaling.XXXXXX)
trap 'rm -rf "$work"' EXIT
spacing0=$(sed -n 's/^ *spacing: *\([0-9.e-]*\).*/\1/p' "$case_file" | head -n 1)
echo "Slope I ($(basename "$case_file"), $(grep '^integration:' "$case_file" | sed 's/ *#.*//')), about $steps steps at the stable step, $threads thread(s); $(nproc) cores, load $(cut -d' ' -f1 /proc/loadavg), $(date -u +%Y-%m-%d)"
# N ~ spacing^-3 from the check's estimate at the case's spacing; the
# stable step ~ spacing (Slope I at 0.289 m: 0.00118 s)
estimate=$("$geoscni" check "$case_file" 2>/dev/null | sed -n 's/^# particles: about \([0-9]*\).*/\1/p')
[ -n "$estimate" ] || { echo "geoscni check $case_file gave no particle estimate" >&2; exit 1; }
printf '%10s %8s %8s %8s %8s %9s %10s %9s %10s %9s %10s\n' particles spacing "pre s" "mesh s" "setup s" "steps/s" "p-steps/s" "pre us/p" "setup us/p" "pre KB/p" "solve KB/p"
for count in $counts; do
    spacing=$(awk -v s="$spacing0" -v n0="$estimate" -v n="$count" \
        'BEGIN { printf "%.4g", s * exp(log(n0 / n) / 3) }')
    end=$(awk -v s="$spacing" -v h0="$spacing0" -v k="$steps" \
        'BEGIN { printf "%.4g", k * 0.9 * 0.00118 * s / h0 }')
    dir=$work/n$count
    mkdir -p "$dir"
    sed -e "s|^geometry: *|geometry: $(dirname "$case_file")/|" \
        -e "s|^\( *spacing:\).*|\1 $spacing|" \
        -e "s|^\( *step:\).*|\1 auto|" \
        -e "s|^\( *ramp:\).*|\1 0|" \
        -e "s|^\( *end:\).*|\1 $end|" \
        -e "s|^\( *every:\).*|\1 1000|" \
        -e "s|^\( *history_every:\).*|\1 1000|" "$case_file" >"$dir/case.yaml"
    /usr/bin/time -f "peak %M KB" "$geoscni" pre -j "$threads" --force \
        "$dir/case.yaml" -o "$dir/out" >"$dir/pre.log" 2>&1 || {
        echo "pre failed at $count particles: $(tail -n 3 "$dir/pre.log")" >&2
        exit 1
    }
    pre_kb=$(sed -n 's/^peak \([0-9]*\) KB$/\1/p' "$dir/pre.log")
    pre_s=$(sed -n 's/^pre: time \([0-9.]*\) s.*/\1/p' "$dir/pre.log")
    mesh_s=$(sed -n 's/^pre: time .* s: meshing \([0-9.]*\) .*/\1/p' "$dir/pre.log")
    /usr/bin/time -f "peak %M KB" "$geoscni" solve -j "$threads" "$dir/case.yaml" \
        -o "$dir/out" >"$dir/solve.log" 2>&1 || {
        echo "solve failed at $count particles: $(grep error "$dir/solve.log")" >&2
        exit 1
    }
    n=$(sed -n 's/^solver: \([0-9]*\) particles.*/\1/p' "$dir/solve.log")
    setup=$(sed -n 's/^solver: .* set up in \([0-9.]*\) s.*/\1/p' "$dir/solve.log")
    rate=$(tr '\r' '\n' <"$dir/solve.log" | grep 'took' | sed 's/.*  \([0-9.e+]*\) particle-steps.*/\1/')
    solve_kb=$(sed -n 's/^peak \([0-9]*\) KB$/\1/p' "$dir/solve.log")
    awk -v n="$n" -v h="$spacing" -v pre="${pre_s:-0}" -v mesh="${mesh_s:-0}" -v setup="$setup" \
        -v rate="$rate" -v pk="$pre_kb" -v sk="$solve_kb" 'BEGIN {
        printf "%10d %8.4g %8.2f %8.2f %8.2f %9.3g %10.3g %9.1f %10.1f %9.2f %10.2f\n",
            n, h, pre, mesh, setup, rate / n, rate, 1e6 * pre / n, 1e6 * setup / n,
            1.024 * pk / n, 1.024 * sk / n }'
done
