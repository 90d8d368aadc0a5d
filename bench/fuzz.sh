#!/bin/sh
# The longer fuzz budget (issue 19, point 2): tests/fuzz/fuzz.py with COUNT
# mutations of each input (case file, geometry, model.h5, results.h5) for
# each SEED, then test_h5_damage flipping one bit at every byte of a
# model.h5. CI runs 15 mutations of seed 1 and every 13th byte.
# Usage: bench/fuzz.sh [BUILD_DIR] [COUNT] [SEEDS]   (default build, 200, "2 3")
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-build}
count=${2:-200}
seeds=${3:-2 3}
status=0
for seed in $seeds; do
    /usr/bin/python3 "$root/tests/fuzz/fuzz.py" "$root/$build/bin/geoscni" \
        --seed "$seed" --count "$count" || status=1
done
(cd "$root/tests/foundation" && "$root/$build/tests/test_h5_damage" 1) | tail -2 || status=1
exit $status
