#!/bin/sh
# Bearing capacity of a smooth rigid strip footing (issue 7, point 2;
# docs/failure.md, "Bearing capacity"): geometries/strip_footing.yaml at
# each spacing and integration, the footing pressure against settlement,
# compared with c N_c = 1.0568 MPa (Prandtl-Reissner with the plane-strain
# match of the paper's Drucker-Prager; REFERENCES.md).
# Prints, per run, the pressure over c N_c at settlements of 2.5%, 5%,
# 7.5%, 10% and 12.5% of the footing width B = 2 m, the largest, the
# largest kinetic/internal energy ratio and the wall time; writes the rows
# to OUT/bearing_capacity.csv. KINEMATICS: small (the case's, the theory
# of the limit load) and/or large (the paper's updated Lagrangian).
# Usage: bench/bearing_capacity.sh [BUILD_DIR] [OUT] [SPACINGS] [METHODS]
#                                  [KINEMATICS]
#        (default build, /tmp/geoscni_bearing, "0.2 0.1", "scni mscni",
#        "small large")
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-build}
out=${2:-/tmp/geoscni_bearing}
spacings=${3:-0.2 0.1}
methods=${4:-scni mscni}
kinematics_list=${5:-small large}
# One mesh per spacing, the same on every run (gmsh's Delaunay, pre's
# default; HXT's meshes move the plateau by about 1%: docs/pre.md).
geoscni=$root/$build/bin/geoscni
. "$root/bench/economy_common.sh" # curve, peak
[ -x "$geoscni" ] || { echo "no $geoscni: build first" >&2; exit 2; }
mkdir -p "$out"
csv=$out/bearing_capacity.csv
# problem, cpu_s and error are the columns bench/accuracy_plot reads
# (bench/bearing_chart.sh): error = |q at 12.5% of B / (c N_c) - 1|, cpu_s
# the CPU time of the solve (pre left out).
echo "spacing,method,kinematics,particles,q_2.5,q_5,q_7.5,q_10,q_12.5,q_max,kinetic_ratio,wall_s,status,problem,cpu_s,error" >"$csv"
echo "strip footing, B = 2 m, q / (c N_c) at settlement / B = 2.5% 5% 7.5% 10% 12.5%, max ($(nproc) cores, load $(cut -d' ' -f1 /proc/loadavg))"
for h in $spacings; do
    for method in $methods; do
    for kinematics in $kinematics_list; do
        case $method in
        scni) integration="scni" ;;
        mscni* | nsni*) # mscni0.5: MSCNI with coefficient 0.5
            weight=${method#*nsni}
            weight=${weight#mscni}
            integration="{method: scni, stabilization: ${method%"$weight"}${weight:+, coefficient: $weight}}" ;;
        dni) integration="dni" ;;
        gauss2 | gauss3) integration="{method: gauss, points: ${method#gauss}}" ;;
        *) echo "unknown method $method (scni, mscni, nsni, mscniC or nsniC with coefficient C, dni, gauss2, gauss3)" >&2; exit 2 ;;
        esac
        run=$out/h${h}_${method}_$kinematics
        mkdir -p "$run"
        # 0.25 m of settlement (12.5% of B) at 0.1 m/s after a 0.5 s ramp.
        sed -e "s|^geometry: *|geometry: $root/geometries/|" \
            -e "s|^\( *spacing:\).*|\1 $h|" \
            -e "s|^integration:.*|integration: $integration|" \
            -e "s|velocity: \[null, null, -0.05\]|velocity: [null, null, -0.1]|" \
            -e "s|^\( *end:\).*|\1 2.75|" \
            -e "s|^\( *every:\).*|\1 0.025|" \
            -e "s|^kinematics:.*|kinematics: $kinematics|" \
            "$root/geometries/strip_footing.yaml" >"$run/strip_footing.yaml"
        start=$(date +%s.%N)
        "$geoscni" pre "$run/strip_footing.yaml" -o "$run" -q
        # A run that stops (exit 3) keeps its rows; the note says where.
        note="" status=ok
        /usr/bin/time -f "%U %S" -o "$run/cpu" \
            "$geoscni" solve "$run/strip_footing.yaml" -o "$run" -q 2>"$run/solve.log" || {
            status=stopped
            note=" (stopped: $(grep -o 'step [0-9]*, t = [0-9.]* s' "$run/solve.log" | head -1))"; }
        wall=$(echo "$start $(date +%s.%N)" | awk '{printf "%.1f", $2 - $1}')
        if [ ! -s "$run/history.csv" ]; then
            echo "  h = $h m, $method, $kinematics kinematics: refused: $(grep -m1 'error' "$run/solve.log")"
            continue
        fi
        particles=$(h5ls "$run/model.h5/particles/position" |
            sed -n 's/.*{\([0-9]*\),.*/\1/p')
        ratio=$(h5dump -a /kinetic_ratio_max "$run/results.h5" 2>/dev/null |
            sed -n 's/.*(0): \(.*\)/\1/p' | head -1)
        # q / (c N_c) at every 2.5% of B = 2 m (0.05 m) to 12.5% and the
        # largest, over the footing area b T = 1 m x 2 h (strip_footing.geo).
        row=$({ curve "$run/history.csv" 0.05 | head -5
                echo "max $(work=$out peak "$(basename "$run")")"; } |
            awk -v scale="$(echo "$h" | awk '{print 1e6 / (2 * $1) / 1.0568e6}')" '
                $1 == "max" { max = $2 * scale; next }
                { q[++n] = $2 * scale }
                END { printf "%.3f,%.3f,%.3f,%.3f,%.3f,%.3f", q[1], q[2], q[3], q[4], q[5], max }')
        cpu=$(tail -1 "$run/cpu" | awk '{printf "%.2f", $1 + $2}')
        error=$(echo "$row" | awk -F, '{ e = $5 - 1; printf "%.5f", e < 0 ? -e : e }')
        echo "$h,$method,$kinematics,$particles,$row,$ratio,$wall,$status,strip_footing_$kinematics,$cpu,$error" >>"$csv"
        echo "  h = $h m ($(echo "$h" | awk '{print 2 / $1}') spacings across B), $method, $kinematics kinematics, $particles particles: $row (q/cNc), kinetic/internal <= $ratio, $wall s$note"
    done
    done
done
echo "rows: $csv"
