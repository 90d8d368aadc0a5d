#!/bin/sh
# The factors of safety of layered and wet slopes that docs/site.md and
# docs/fos.md quote (issue 22), each a `geoscni fos` study:
# - Griffiths & Lane (1999) example 5, slow drawdown, L/H = 0, 0.2, 0.4,
#   0.5, 0.7, 0.9 (1 m; tests/solver/cases/gl_slope.yaml with the water L
#   below the crest, gamma_w / gamma = 0.5);
# - their example 4 geometry (tests/solver/cases/gl_layers.yaml), lambda =
#   0.5, 1, 2 at 1 m and lambda = 2 at 0.5 m;
# - the same undrained slope on a rigid base at its toe (no interface;
#   geometries/slope_gl.geo, c = 50 kPa, phi = 0) at 1 and 0.5 m;
# - geometries/slope_site.yaml at 1 m and 0.5 m.
# Prints a table: case, factor of safety, wall time. About 15 minutes on
# 2 cores.
# Usage: bench/fos_site.sh [BUILD_DIR] [OUT]  (default build, a temporary
#        folder)
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-build}
geoscni=$root/$build/bin/geoscni
[ -x "$geoscni" ] || { echo "no $geoscni: build first" >&2; exit 2; }
out=${2:-$(mktemp -d /tmp/geoscni_fos_site.XXXXXX)}
mkdir -p "$out"
cases=$root/tests/solver/cases
study() { # NAME CASE
    start=$(date +%s)
    "$geoscni" fos "$2" -o "$out/$1" --no-pictures >"$out/$1.log" 2>&1 ||
        { echo "$1: fos failed: $(tail -2 "$out/$1.log")"; return; }
    printf "%-28s %s  %4d s\n" "$1" "$(sed -n 's/^factor of safety: //p' "$out/$1.log")" \
        "$(($(date +%s) - start))"
}
printf "%-28s %s  %s\n" "case" "FS" "wall"
for ratio in 0 0.2 0.4 0.5 0.7 0.9; do
    level=$(awk -v r="$ratio" 'BEGIN { printf "%g", 10 - 10 * r }')
    sed -e "s|^geometry: .*|geometry: $root/geometries/slope_gl.geo|" \
        -e "s|^geostatic: on|geostatic: on\nwater: {level: $level, unit_weight: 10000}|" \
        "$cases/gl_slope.yaml" >"$out/drawdown_$ratio.yaml"
    study "drawdown_L_over_H_$ratio" "$out/drawdown_$ratio.yaml"
done
for lambda in 0.5 1 2; do
    c2=$(awk -v l="$lambda" 'BEGIN { printf "%g", 50 * l }')
    sed -e "s|^geometry: .*|geometry: $root/geometries/slope_gl_layers.geo|" \
        -e "s|cohesion: 100.0e3|cohesion: ${c2}.0e3|" "$cases/gl_layers.yaml" >"$out/layers_$lambda.yaml"
    study "two_layers_lambda_$lambda" "$out/layers_$lambda.yaml"
done
sed -e "s|spacing: 1.0|spacing: 0.5|" "$out/layers_2.yaml" >"$out/layers_2_fine.yaml"
study "two_layers_lambda_2_0.5m" "$out/layers_2_fine.yaml"
for spacing in 1.0 0.5; do
    sed -e "s|^geometry: .*|geometry: $root/geometries/slope_gl.geo|" \
        -e "s|cohesion: 10.0e3, friction_angle: 20|cohesion: 50.0e3, friction_angle: 0|" \
        -e "s|spacing: 1.0|spacing: $spacing|" "$cases/gl_slope.yaml" >"$out/undrained_$spacing.yaml"
    study "undrained_rigid_base_$spacing" "$out/undrained_$spacing.yaml"
done
for spacing in 1.0 0.5; do
    sed -e "s|^geometry: .*|geometry: $root/geometries/slope_site.geo|" \
        -e "s|spacing: 0.5|spacing: $spacing|" "$root/geometries/slope_site.yaml" >"$out/slope_site_$spacing.yaml"
    study "slope_site_$spacing" "$out/slope_site_$spacing.yaml"
done
echo "logs and studies in $out"
