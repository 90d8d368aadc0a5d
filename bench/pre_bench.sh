#!/bin/sh
# Times geoscni pre on Slope I at paper resolution (issue 3, point 5): gmsh
# meshing, Delaunay neighbours, clipped cells, checks and writing, on 2
# threads, three runs; prints each run's split and the median run.
# Target: under 15 s in total on 2 cores.
# Usage: bench/pre_bench.sh [BUILD_DIR] [RUNS]   (default build-pre, 3)
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-build-pre}
runs=${2:-3}
geoscni=$root/$build/bin/geoscni
[ -x "$geoscni" ] || { echo "no $geoscni: build first" >&2; exit 2; }
work=$(mktemp -d /tmp/geoscni_pre_bench.XXXXXX)
trap 'rm -rf "$work"' EXIT
echo "geoscni pre geometries/slope_I.yaml on 2 threads, $runs runs ($(nproc) cores, load $(cut -d' ' -f1 /proc/loadavg))"
i=1
while [ "$i" -le "$runs" ]; do
    "$geoscni" pre -j 2 "$root/geometries/slope_I.yaml" -o "$work/out" >"$work/log.$i"
    grep '^pre: [0-9]* particles' "$work/log.$i" | cut -d, -f1
    grep '^pre: time' "$work/log.$i" | sed "s/ -> .*//; s/^pre: /run $i: /"
    i=$((i + 1))
done
echo "median:"
grep -h '^pre: time' "$work"/log.* | sed 's/ -> .*//' |
    sort -t' ' -k3,3g | sed -n "$(((runs + 1) / 2))p"
