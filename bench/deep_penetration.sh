#!/bin/sh
# Deep penetration of a rigid strip footing into weightless Tresca clay
# (issue 15, point 6; docs/deep_penetration.md): geometries/footing_penetration.yaml
# with the large kinematics and reference-configuration updates, at each
# SPACING (B / spacing particles across the footing) and each FOOTING
# (smooth: x free under the footing; rough: x held). Prints q / s_u at every
# 0.05 B of settlement (q the footing's net force over its area B/2 x the
# slab thickness 2 h of the half model; s_u = 1 kPa) and where each run
# ended. geoscni run skips a case whose results are up to date. The footing
# is a rigid body (rigid: true: side walls the soil cannot pass, and a
# smooth footing's particles that slide out past its edge let go;
# docs/solver.md, "Rigid bodies"); RIGID=0 makes it its base alone.
# Draws OUT/penetration_FOOTING.png (bench/penetration_plot.c) when built.
# Usage: [RIGID=0] bench/deep_penetration.sh [BUILD_DIR] [OUT] [SPACINGS] [FOOTINGS] [UPDATE]
#        (default build, out/penetration, "0.2 0.1", "smooth rough",
#         "{strain: 0.2, min_steps: 20}")
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-build}
out=${2:-$root/out/penetration}
spacings=${3:-0.2 0.1}
footings=${4:-smooth rough}
update=${5:-"{strain: 0.2, min_steps: 20}"}
rigid=$([ "${RIGID:-1}" = 0 ] || echo ", rigid: true")
geoscni=$root/$build/bin/geoscni
[ -x "$geoscni" ] || { echo "no $geoscni: build first" >&2; exit 2; }
mkdir -p "$out"
source_case=$root/geometries/footing_penetration.yaml
for h in $spacings; do
    for footing in $footings; do
        name=${footing}_h$h
        case $footing in
        smooth) velocity="[null, null, -0.1]" ;;
        rough) velocity="[0, null, -0.1]" ;;
        *) echo "unknown footing $footing (smooth or rough)" >&2; exit 2 ;;
        esac
        {
            echo "kinematics: large"
            echo "reference_update: $update"
            sed -e "s|^geometry: *|geometry: $root/geometries/|" \
                -e "s|^\( *spacing:\).*|\1 $h|" \
                -e "s|^\( *footing:\).*|\1 {velocity: $velocity$rigid}|" "$source_case"
        } >"$out/$name.yaml"
        t0=$(date +%s)
        status=0
        GEOSCNI_REPRODUCIBLE=1 "$geoscni" run "$out/$name.yaml" -o "$out/$name" -q \
            --no-pictures >"$out/$name.log" 2>&1 || status=$?
        updates=$(awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) if ($i == "reference_updates") c = i }
            END { print c ? $c : 0 }' "$out/$name/history.csv")
        echo "$name: B / h = $(echo "$h" | awk '{printf "%.0f", 1 / $1}'), exit $status, $(($(date +%s) - t0)) s ($updates updates)"
        grep 'error:' "$out/$name.log" | head -1 | cut -c1-220 | sed 's/^/  /' || true
        awk -F, -v h="$h" '
            NR == 1 { for (i = 1; i <= NF; ++i) col[$i] = i; next }
            {
                w = -$col["footing_uz_m"]; q = -$col["footing_fz_N"] / (0.5 * 2 * h) / 1000
                k = int(w / 0.05 + 1e-6)
                if (k > last && k * 0.05 <= w + 1e-9) { line = line sprintf(" %.2f:%.2f", k * 0.05, q); last = k }
                end = w
            }
            END { printf "  w/B:q/s_u%s\n  ended at %.3f B\n", line, end }' "$out/$name/history.csv"
    done
done
# the charts: each footing's runs against Prandtl and Salgado
plot=$root/$build/bin/penetration_plot
if [ -x "$plot" ]; then
    for footing in $footings; do
        set --
        for h in $spacings; do
            [ -f "$out/${footing}_h$h/history.csv" ] &&
                set -- "$@" "$out/${footing}_h$h/history.csv" \
                    "$footing, B/$(echo "$h" | awk '{printf "%.0f", 1 / $1}')" \
                    "$(echo "$h" | awk '{print 0.5 * 2 * $1}')"
        done
        [ $# -gt 0 ] && "$plot" "$out/penetration_$footing.png" "$@" &&
            echo "chart: $out/penetration_$footing.png"
    done
fi
