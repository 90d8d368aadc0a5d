#!/bin/sh
# Issue 18, point 4 and its speed goal: `geoscni fos` of Griffiths & Lane's
# slope (geometries/slope_gl.yaml: a 2:1 slope 10 m high, c'/(gamma H) =
# 0.05, phi' = 20, psi = 0, plane strain) at SPACING (default 0.27 m: about
# 10,000 particles), on THREADS threads (default 2). Prints the trials, the
# factor of safety, the particle count and the whole study's wall time
# (pre, trials, the mechanism's post); the goal is under 10 minutes on 2
# cores. References: 1.38 (Bishop & Morgenstern's charts), 1.4 (Griffiths &
# Lane's finite elements); docs/fos.md.
# MASS_SCALING=F sets the case's time.mass_scaling (fos's default, when the
# case sets none, is 0.01; MASS_SCALING=0 runs the study without it); the
# last line adds the steps and wall time of the trials (fos.csv).
# Usage: [MASS_SCALING=F] bench/fos_slope.sh [BUILD_DIR] [OUT] [SPACING]
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-build}
out=${2:-$root/out/fos_slope}
spacing=${3:-0.27}
threads=${THREADS:-2}
geoscni=$root/$build/bin/geoscni
[ -x "$geoscni" ] || { echo "no $geoscni: build first" >&2; exit 2; }
mkdir -p "$out"
case=$out/slope_gl_$spacing.yaml
sed -e "s|^geometry: *|geometry: $root/geometries/|" \
    -e "s|^  spacing: .*|  spacing: $spacing|" \
    -e "${MASS_SCALING:+s|^\( *\)step:.*|&\n\1mass_scaling: $MASS_SCALING|}" \
    "$root/geometries/slope_gl.yaml" >"$case"
start=$(date +%s.%N)
"$geoscni" fos "$case" -o "$out/fos_$spacing" --rerun -j "$threads" | grep -v "^pre:"
end=$(date +%s.%N)
particles=$(/usr/bin/python3 -c "import h5py; print(h5py.File('$out/fos_$spacing/model.h5')['particles/position'].shape[0])")
trials=$(awk -F, 'NR == 2 { for (k = 1; k <= NF; ++k) c[$k] = k }
    NR > 2 { n += $c["steps"]; w += $c["wall_s"] } END { printf "%d steps, %.0f s", n, w }' \
    "$out/fos_$spacing/fos.csv")
awk -v s="$start" -v e="$end" -v n="$particles" -v t="$threads" -v h="$spacing" -v trials="$trials" \
    'BEGIN { printf "fos_slope: spacing %s m, %d particles, %d threads: %.0f s for the whole study (the trials: %s)\n", h, n, t, e - s, trials }'
