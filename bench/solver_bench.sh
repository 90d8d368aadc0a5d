#!/bin/sh
# Speed of the explicit loop (issue 5, point 7): particle-steps per second of
# the full step (kinematics, Hughes-Winget + damage + Drucker-Prager, forces,
# boundary values) on Slope I at paper resolution, on 1 and on 2 threads,
# RUNS runs each; prints every run and the medians. The model is made once
# by pre; each run solves STEPS steps at the paper's time step and writes
# only its first and last frames; a run's line ends with where its step
# time went (row pass, boundary solves, updates, and the shares of the
# pass's gather, material, stabilization and scatter since 2026-12-07;
# nothing from a build older than that report). INTEGRATION replaces the case's
# integration (e.g. scni for plain SCNI; slope_I.yaml has MSCNI); THREADS
# lists the thread counts to run.
# LOADED=T measures the pass with damage and plasticity at work: the
# footing at 5 times the case's speed (its ramp kept) is first solved to T
# s once, and every run restarts from that state for STEPS steps (Slope I
# with plain SCNI: T = 2 is past the peak, damage up to 0.85).
# WINDOW_CUT="C1 C2 ..." sets kernel.window_cut (docs/kernels.md, "Window
# cut"): one value, or a list to compare, each with its own loading run,
# whose runs alternate (C1, C2, ..., then again) so that the host's drift
# falls on all alike; the medians of each and their ratios to the first's.
# BUILDS="B1 B2 ..." compares builds (folders under the repository, or
# absolute) the same way: their runs alternate on the same model and, with
# LOADED, restart from the same state (loaded by the first build); with
# WINDOW_CUT, every build runs every cut. BUILD_DIR then only names the
# folder whose stream program measures STREAM. Besides the ratio of the
# medians, each run is set against the first variant's run of its round:
# the median of those ratios and how many are above 1 (on a host whose
# speed drifts by 20%, steadier than the medians' ratio).
# UPDATE_EVERY=K adds a reference-configuration update every K steps (issue
# 15, point 4): the rate then includes them, and each run's line their count
# and share of the solve. Without UPDATE_EVERY the rate leaves out the
# first factorization of the boundary matrices (a set-up cost; since
# 2026-12-07 the stable step makes it before the loop, where builds before
# made it in the first step: 0.21 s of a 200-step run on 2 threads, 10% of
# its wall time).
# After the medians: the parallel efficiency, the step's least data
# (gsn_explicit_step_bytes) against STREAM triad measured on as many threads
# (bench/stream.c) with the roof it puts on the rate, and the peak resident
# memory a particle (GNU time).
# WAIT_POLICY=passive (or active) runs geoscni with that OMP_WAIT_POLICY;
# unset, geoscni waits at its barriers as users run it (its own short spin,
# GOMP_SPINCOUNT=3000). Until 2026-12-07 the bench always set passive:
# on a Zen 3 VM plain SCNI then ran 1.12 times slower on 2 threads
# (docs/solver.md, "2026-12-07, midnight").
# MODEL=PATH solves that model.h5 instead of making one: to compare two
# builds on one model (gmsh's HXT meshes differ from run to run, and so do
# the costs they give; copy the first run's with KEEP_MODEL=PATH).
# Usage: bench/solver_bench.sh [BUILD_DIR] [RUNS] [STEPS] [CASE] [INTEGRATION]
#        (default build, 3, 300, geometries/slope_I.yaml, the case's)
#        THREADS="1 2" (default), LOADED, WINDOW_CUT, BUILDS, UPDATE_EVERY,
#        WAIT_POLICY, MODEL and KEEP_MODEL (unset) in the environment
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-build}
runs=${2:-3}
steps=${3:-300}
case_file=${4:-$root/geometries/slope_I.yaml}
integration=${5:-}
thread_counts=${THREADS:-1 2}
wait_policy=${WAIT_POLICY:+OMP_WAIT_POLICY=$WAIT_POLICY}
# the geoscni of build folder $1 (under the repository, or absolute)
geoscni_of() {
    case $1 in
    /*) echo "$1/bin/geoscni" ;;
    *) echo "$root/$1/bin/geoscni" ;;
    esac
}
builds=${BUILDS:-$build}
for b in $builds; do
    [ -x "$(geoscni_of "$b")" ] || { echo "no $(geoscni_of "$b"): build first" >&2; exit 2; }
done
geoscni=$(geoscni_of "${builds%% *}")
work=$(mktemp -d /tmp/geoscni_solver_bench.XXXXXX)
trap 'rm -rf "$work"' EXIT
loaded=${LOADED:-}
# The case with the run cut to STEPS steps of 1e-3 s (and no ramp, which
# may be longer than the cut run); with LOADED, STEPS steps after T s, the
# footing 5 times faster and the ramp kept.
if [ -n "$loaded" ]; then
    speed=$(sed -n 's/.*footing: *{velocity: \[null, null, -\([0-9.e-]*\)\]}.*/\1/p' "$case_file")
    fast=$(echo "$speed" | awk '{print $1 * 5}')
    sed -e "s|^geometry: *|geometry: $(dirname "$case_file")/|" \
        -e "s|velocity: \[null, null, -$speed\]|velocity: [null, null, -$fast]|" \
        -e "s|^\( *end:\).*|\1 $(echo "$loaded $steps" | awk '{print $1 + $2 * 1e-3}')|" \
        -e "s|^\( *every:\).*|\1 1000|" "$case_file" >"$work/case.yaml"
else
    sed -e "s|^geometry: *|geometry: $(dirname "$case_file")/|" \
        -e "s|^\( *end:\).*|\1 $(echo "$steps" | awk '{print $1 * 1e-3}')|" \
        -e "s|^\( *ramp:\).*|\1 0|" \
        -e "s|^\( *every:\).*|\1 1000|" "$case_file" >"$work/case.yaml"
fi
if [ -n "$integration" ]; then
    sed -i -e "s|^integration:.*|integration: $integration|" "$work/case.yaml"
fi
if [ -n "${UPDATE_EVERY:-}" ]; then
    step=$(sed -n 's/^ *step: *\([0-9.e-]*\).*/\1/p' "$work/case.yaml")
    echo "reference_update: {every: $(echo "$UPDATE_EVERY ${step:-1e-3}" | awk '{print $1 * $2}'), min_steps: 1}" >>"$work/case.yaml"
fi
if [ -n "${MODEL:-}" ]; then
    mkdir -p "$work/out" && cp "$MODEL" "$work/out/model.h5"
else
    "$geoscni" pre "$work/case.yaml" -o "$work/out" -q
fi
[ -n "${KEEP_MODEL:-}" ] && cp "$work/out/model.h5" "$KEEP_MODEL"
mv "$work/out" "$work/model"
# the variants: the case as it is, or one case a window cut, each with
# every build (BUILD@CUT, the first build's first)
cuts=${WINDOW_CUT:--}
variants=
for cut in $cuts; do
    for b in $builds; do variants="$variants $b@$cut"; done
done
for cut in $cuts; do
    cp "$work/case.yaml" "$work/case.$cut.yaml"
    [ "$cut" = - ] ||
        sed -i -e "s|^\( *\)support:\(.*\)|\1support:\2\n\1window_cut: $cut|" "$work/case.$cut.yaml"
    cp -r "$work/model" "$work/start.$cut"
done
restart=
if [ -n "$loaded" ]; then
    for cut in $cuts; do
        sed -e "s|^\( *end:\).*|\1 $loaded|" "$work/case.$cut.yaml" >"$work/load.yaml"
        "$geoscni" solve "$work/load.yaml" -o "$work/start.$cut" -q || {
            echo "the loading run to $loaded s failed: see above" >&2
            exit 1
        }
        echo "loaded to t = $loaded s (footing at $fast m/s)$([ "$cut" = - ] || echo ", window cut $cut"): max damage $(awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) if ($i == "max_damage") c = i } END { print $c }' "$work/start.$cut/history.csv")"
    done
    restart=--restart
fi
echo "geoscni solve $(basename "$case_file") ($(grep '^integration:' "$work/case.yaml" | sed 's/ *#.*//')), $steps steps, $runs runs per thread count ($(nproc) cores, load $(cut -d' ' -f1 /proc/loadavg))"
# a variant's name in file names, and in the lines printed
key() { echo "$1" | tr '/@' '__'; }
label() {
    [ "$builds" = "$build" ] || printf ', %s' "${1%@*}"
    [ "${1##*@}" = - ] || printf ', cut %s' "${1##*@}"
}
for threads in $thread_counts; do
    i=1
    for v in $variants; do : >"$work/rates.$threads.$(key "$v")"; done
    while [ "$i" -le "$runs" ]; do
        for v in $variants; do
            cut=${v##*@}
            rm -rf "$work/out"
            cp -r "$work/start.$cut" "$work/out"
            env $wait_policy /usr/bin/time -f "peak %M KB" "$(geoscni_of "${v%@*}")" solve "$work/case.$cut.yaml" -o "$work/out" -j "$threads" \
                $restart >"$work/log" 2>&1 || {
                echo "  $threads thread(s)$(label "$v"), run $i failed: $(grep 'error:' "$work/log")" >&2
                exit 1
            }
            rate=$(tr '\r' '\n' <"$work/log" | grep 'took' | sed 's/.*  \([0-9.e+]*\) particle-steps.*/\1/')
            particles=$(grep '^solver: [0-9]* particles' "$work/log" | sed 's/solver: \([0-9]*\) particles.*/\1/')
            # without the factorization of the boundary matrices, a set-up
            # cost that falls in the loop or before it as the build does it
            # (since 2026-12-07 the stable step's projection makes it before);
            # with UPDATE_EVERY the updates' factorizations are theirs: kept
            factor=
            [ -n "${UPDATE_EVERY:-}" ] ||
                factor=$(sed -n 's/.*besides, \([0-9.e+-]*\) s factorizing.*/\1/p' "$work/log")
            rate=$(awk -v r="$rate" -v n="$particles" -v s="$steps" -v f="${factor:-0}" \
                'BEGIN { printf "%.3g", n * s / (n * s / r - f) }')
            phases=$(grep '^step time:' "$work/log" | sed 's/^step time: //')
            updates=$(grep '^reference updates:' "$work/log" | sed 's/^reference updates: \([0-9]*\) .*, \([0-9.e+-]* s\), \([0-9.]*%\) of the solve.*/\1 updates, \2, \3 of the solve/')
            echo "  $threads thread(s)$(label "$v"), run $i: $rate particle-steps/s ($particles particles)${phases:+; $phases}${updates:+; $updates}"
            echo "$rate" >>"$work/rates.$threads.$(key "$v")"
            sed -n 's/^step data: \([0-9.]*\) kB.*/\1/p' "$work/log" >"$work/bytes.$(key "$v")"
            sed -n 's/^peak \([0-9]*\) KB$/\1/p' "$work/log" >"$work/peak.$(key "$v")"
        done
        i=$((i + 1))
    done
done
# The medians; against one thread's, the parallel efficiency; against
# STREAM triad on as many threads (bench/stream.c, measured now), the
# memory traffic of the step's least data (gsn_explicit_step_bytes) and the
# rate at which that data alone would fill the bandwidth (the roof).
stream=$root/$build/bin/stream
for threads in $thread_counts; do
    triad=
    [ -x "$stream" ] && triad=$("$stream" "$threads" | sed -n 's/.*: \([0-9.]*\) GB\/s$/\1/p')
    first=
    first_key=
    for v in $variants; do
        k=$(key "$v")
        [ -n "$first_key" ] || first_key=$k
        # each run against the first variant's run of the same round (they
        # alternate, so the host's drift falls on both): the median of those
        # ratios and how many are above 1, steadier than the medians' ratio
        pairs=
        [ "$k" = "$first_key" ] ||
            pairs=$(paste "$work/rates.$threads.$first_key" "$work/rates.$threads.$k" |
                awk '{ print $2 / $1 }' | sort -g |
                awk '{ r[NR] = $1; if ($1 > 1) up++ } END { printf "%.2f %d %d", r[int((NR + 1) / 2)], up, NR }')
        median=$(sort -g "$work/rates.$threads.$k" | sed -n "$(((runs + 1) / 2))p")
        one=$(sort -g "$work/rates.1.$k" 2>/dev/null | sed -n "$(((runs + 1) / 2))p")
        [ -n "$first" ] || first=$median
        awk -v t="$threads" -v m="$median" -v one="$one" -v kb="$(cat "$work/bytes.$k")" \
            -v s="${triad:-0}" -v peak="$(cat "$work/peak.$k")" -v n="$particles" \
            -v name="$(label "$v")" -v first="$first" -v pairs="$pairs" 'BEGIN {
            line = sprintf("median, %d thread(s)%s: %.3g particle-steps/s", t, name, m)
            if (name != "" && m != first)
                line = line sprintf(" (%.2f x the first'"'"'s)", m / first)
            if (split(pairs, p, " ") == 3)
                line = line sprintf(" (run by run: median %.2f x the first'"'"'s, %d of %d above)", p[1], p[2], p[3])
            if (one != "" && t > 1)
                line = line sprintf(" (parallel efficiency %.2f)", m / (t * one))
            if (kb > 0 && s > 0)
                line = line sprintf("; step data %.2f kB a particle-step: %.1f GB/s, %.0f%% of STREAM triad %.1f GB/s, roof %.3g particle-steps/s",
                    kb, m * kb * 1e-6, 100 * m * kb * 1e-6 / s, s, s * 1e6 / kb)
            if (peak > 0 && n > 0)
                line = line sprintf("; peak memory %.1f kB a particle", 1.024 * peak / n)
            print line }'
    done
done
