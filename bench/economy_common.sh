# Shared by the economy benches and bearing_capacity.sh (sourced): run, peak, particles and step
# need $geoscni, $work, $end and $threads (economy_setup sets them); curve
# needs nothing.

# economy_setup NAME: threads (THREADS, default 2), the geoscni of $root's
# $build (exit 2 if not built), the work folder (WORK, or a new one under
# /tmp), and the run's first line.
economy_setup() {
    threads=${THREADS:-2}
    geoscni=$root/$build/bin/geoscni
    [ -x "$geoscni" ] || { echo "no $geoscni: build first" >&2; exit 2; }
    work=${WORK:-$(mktemp -d "/tmp/geoscni_economy_$1.XXXXXX")}
    mkdir -p "$work"
    echo "economy_$1: time.end $end s, $threads threads, $(nproc) cores, load $(cut -d' ' -f1 /proc/loadavg), work in $work"
}

# curve HISTORY [STEP]: the footing load (MN) at every STEP m of settlement
# (default 0.025), interpolated linearly between the history's rows.
curve() {
    awk -F, -v step="${2:-0.025}" '
        NR == 1 { for (i = 1; i <= NF; ++i) { if ($i ~ /^footing_uz(_m)?$/) u = i; if ($i ~ /^footing_fz(_N)?$/) f = i }; next }
        { s = -$u; q = -$f / 1e6
          while (next_s + step <= s + 1e-12) { next_s += step
              printf "%.3f %.6f\n", next_s, prev_q + (q - prev_q) * (next_s - prev_s) / (s - prev_s) }
          prev_s = s; prev_q = q }' "$1"
}

# run NAME CASE: the case cut to END s, pre + solve; prints the wall time.
run() {
    sed -e "s|^geometry: *|geometry: $(cd "$(dirname "$2")" && pwd)/|" \
        -e "s|^\( *end:\).*|\1 $end|" \
        -e "s|^\( *every:\).*|\1 $(echo "$end" | awk '{print $1 / 50}')|" \
        "$2" >"$work/$1.yaml"
    start=$(date +%s.%N)
    "$geoscni" pre "$work/$1.yaml" -o "$work/$1" >"$work/$1.pre.log"
    OMP_WAIT_POLICY=passive "$geoscni" solve "$work/$1.yaml" -o "$work/$1" \
        -j "$threads" >"$work/$1.log" 2>&1
    stop=$(date +%s.%N)
    echo "$start $stop" | awk '{printf "%.1f", $2 - $1}'
}

# peak NAME [FACTOR]: the largest |footing_fz| of the history times FACTOR
# (default 1), in MN, and the settlement where it occurs.
peak() {
    awk -F, -v factor="${2:-1}" '
        NR == 1 { for (i = 1; i <= NF; ++i) { if ($i ~ /^footing_fz(_N)?$/) f = i; if ($i ~ /^footing_uz(_m)?$/) u = i } next }
        { v = ($f < 0 ? -$f : $f) * factor; if (v > best) { best = v; at = -$u } }
        END { printf "%.4f %.4f", best / 1e6, at }' "$work/$1/history.csv"
}

particles() { grep '^solver: [0-9]* particles' "$work/$1.log" | sed 's/solver: \([0-9]*\) particles.*/\1/'; }
step() { grep '^time step:' "$work/$1.log" | sed 's/time step: \([0-9.e+-]*\) s.*/\1/'; }
